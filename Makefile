# wrsim: `make testbench` runs the benches, `make test` the test suite. Both set up the machine first.
VENV := .venv
ifdef COMPILE
export WRSIM_COMPILE := $(COMPILE)
endif

.DEFAULT_GOAL := help
.PHONY: help setup testbench convergence regression report-check lint unit acceptance test bench bench-study study score fleet calibrate fuzz clean

help:
	@echo "wrsim make targets:"
	@echo "  make setup       install ngspice >= 42, GHDL and the Python venv ($(VENV)) if missing (ci/setup.sh)"
	@echo "  make testbench   run all benches, compare with the measurements, write build/results/"
	@echo "                   BENCH=<name> runs one bench, PARAMS=<name> uses params/<name>.txt; exits 0 when only"
	@echo "                   KNOWN deviations (testbenches/known.toml) remain, 1 on a FAIL, an error or a regression"
	@echo "  make convergence the compliance bench (BENCH= another) also at reltol 1e-4 (RELTOL=): every metric at both"
	@echo "                   tolerances and the verdicts that change, on its page (convergence.csv); PARAMS= as above"
	@echo "  make regression  every bench's waveforms against its reference (testbenches/golden/) in tolerance tubes;"
	@echo "                   pages of failing signals in build/results/regression/; PARAMS=, BENCH= as above;"
	@echo "                   BLESS='why' makes the results the new references (recorded in BLESSINGS.tsv)"
	@echo "  make report-check  the HTML report of build/results in headless Chromium: screenshots, and every"
	@echo "                   JavaScript error, failed load, broken image and broken link"
	@echo "  make lint        ruff check, ruff format --check and mypy"
	@echo "  make unit        the unit and fuzzing tests (tests/unit, tests/fuzz)"
	@echo "  make acceptance  the end-to-end bench tests (tests/acceptance)"
	@echo "  make test        lint, then the unit, fuzzing and acceptance tests in one pytest run"
	@echo "  make bench       time every bench: wall, lowering, ngspice (wrsim bench); warm starts against cold runs"
	@echo "  make bench-study time tolerance studies: 1000 open-loop strokes, 100 closed-loop pinches, samples per"
	@echo "                   second local vs Dask with 1 and 2 workers (about 20 min on 2 cores)"
	@echo "  make study       a tolerance study: BENCH=<name> (default stroke), SAMPLES=, SEED=, TOLERANCES= (default"
	@echo "                   tolerances/production), STUDY_ARGS='...' (wrsim study --help; docs/tolerance-studies.md)"
	@echo "  make score       every anti-pinch algorithm (params/antipinch/) on the compliance matrix and the drum"
	@echo "                   bench: worst peak per regulation, false reversals, latency (build/results/score/);"
	@echo "                   ALGORITHM=<name or file> scores one, C_ALGORITHM=<file.c> a C file of your own"
	@echo "  make fleet       every VHDL algorithm on the scenario catalog (testbenches/scenarios/catalog) over SAMPLES="
	@echo "                   doors (default 10) drawn from the production and ambient spreads, SEED=; replayed on"
	@echo "                   records kept in build/work/fleet/ (a second run resumes; build/results/fleet/);"
	@echo "                   ECU=pwm records the closings with the PWM ECU (its algorithm 7 scored too)"
	@echo "  make calibrate   ALGORITHM= (default observer_rise): its declared calibration values searched on the catalog's"
	@echo "                   tuning cases over SAMPLES= doors, TRIALS= (default 60), ECU=; build/calibrated/<algorithm>.txt"
	@echo "  make fuzz        mutation fuzzing: 100,000 VHDL-AMS and 20,000 data-file cases (parameter sets and their"
	@echo "                   includes, tolerance laws, tables, CAN, scenario files, replay records; counts of tracebacks,"
	@echo "                   cases over 10 s or 1 GB), then 200 accepted corpus mutants run by wrsim run (runs"
	@echo "                   over 120 s, processes left) and 40 accepted scenario mutants by wrsim scenario (an"
	@echo "                   ERROR row is a late error); FUZZ_ARGS='--vhdl N --data M --run R --scenarios K --seed S'"
	@echo "  make clean       remove build/"
	@echo "COMPILE=0 with any target: the equations as behavioural sources instead of compiled device code (OSDI),"
	@echo "  about 3x more ngspice time on the closed-loop benches (WRSIM_COMPILE; docs/performance.md)"

setup:
	bash ci/setup.sh

testbench: setup
	$(VENV)/bin/wrsim testbench $(if $(BENCH),--bench $(BENCH)) $(if $(PARAMS),--params $(PARAMS))

convergence: setup
	$(VENV)/bin/wrsim testbench --bench $(or $(BENCH),compliance) --convergence $(or $(RELTOL),1e-4) $(if $(PARAMS),--params $(PARAMS))

regression: setup
	$(VENV)/bin/wrsim regression $(if $(BENCH),--bench $(BENCH)) $(if $(PARAMS),--params $(PARAMS)) \
	  $(if $(BLESS),--bless --reason "$(BLESS)")

report-check: setup
	$(VENV)/bin/wrsim report-check

lint: setup
	$(VENV)/bin/ruff check tools tests
	$(VENV)/bin/ruff format --check tools tests
	$(VENV)/bin/mypy

unit: setup
	$(VENV)/bin/pytest tests/unit tests/fuzz

acceptance: setup
	$(VENV)/bin/pytest tests/acceptance

test: lint
	$(VENV)/bin/pytest

bench: setup
	$(VENV)/bin/wrsim bench $(if $(BENCH),--bench $(BENCH))
	$(if $(BENCH),,$(VENV)/bin/wrsim bench --warm)

bench-study: setup
	$(VENV)/bin/wrsim bench --study

study: setup
	$(VENV)/bin/wrsim study $(or $(BENCH),stroke) --params $(or $(TOLERANCES),tolerances/production) \
	  --samples $(or $(SAMPLES),100) --seed $(or $(SEED),1) $(STUDY_ARGS)

score: setup
	$(VENV)/bin/wrsim score $(if $(PARAMS),--params $(PARAMS)) $(if $(ALGORITHM),--algorithm $(ALGORITHM)) $(if $(C_ALGORITHM),--c-algorithm $(C_ALGORITHM))

FLEET := --fleet tolerances/production --fleet tolerances/ambient --samples $(or $(SAMPLES),10) --seed $(or $(SEED),1)

fleet: setup
	$(VENV)/bin/wrsim score $(FLEET) $(if $(ALGORITHM),--algorithm $(ALGORITHM)) $(if $(ECU),--ecu $(ECU))

calibrate: setup
	$(VENV)/bin/wrsim calibrate $(or $(ALGORITHM),observer_rise) $(FLEET) --trials $(or $(TRIALS),60) $(if $(ECU),--ecu $(ECU))

fuzz: setup
	$(VENV)/bin/python tests/fuzz/fuzzer.py $(FUZZ_ARGS)

clean:
	rm -rf build
