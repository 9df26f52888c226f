# wrsim: `make testbench` runs the benches, `make test` the test suite. Both set up the machine first.
VENV := .venv

.DEFAULT_GOAL := help
.PHONY: help setup testbench test bench clean

help:
	@echo "wrsim make targets:"
	@echo "  make setup       install ngspice >= 42, GHDL and the Python venv ($(VENV)) if missing (ci/setup.sh)"
	@echo "  make testbench   run all benches, compare with the measurements, write build/results/"
	@echo "                   BENCH=<name> runs one bench, PARAMS=<name> uses params/<name>.txt"
	@echo "  make test        lint (ruff, mypy), then the unit and acceptance tests (pytest)"
	@echo "  make bench       time every bench: wall, lowering, ngspice (wrsim bench)"
	@echo "  make clean       remove build/"

setup:
	bash ci/setup.sh

testbench: setup
	$(VENV)/bin/wrsim testbench $(if $(BENCH),--bench $(BENCH)) $(if $(PARAMS),--params $(PARAMS))

test: setup
	$(VENV)/bin/ruff check tools tests
	$(VENV)/bin/pytest

bench: setup
	$(VENV)/bin/wrsim bench $(if $(BENCH),--bench $(BENCH))

clean:
	rm -rf build
