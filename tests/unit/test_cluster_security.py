"""A Dask scheduler is talked to securely (wrsim.study.cluster): a study runs on a TLS cluster with the certificates
the options name and gives the local result; a plain address to another machine is refused before any connection
unless --insecure; a certificate that cannot be read or a handshake that fails is one error naming the file or the
address; a worker whose simulators or model library differ from this machine's is one error naming it."""

from __future__ import annotations

import dataclasses
import logging
import os
import socket
from pathlib import Path

import dask
import distributed
import pytest
from distributed import LocalCluster, Security

from wrsim import cli
from wrsim.study import StudySpec, Task, cluster, draw, factors, read_study, run_sample, sample_set, study_params

STUDY = ["study", "stroke", "--params", "tolerances/production", "--samples", "2", "--stop", "0.5"]


def one_error(capsys, argv: list[str]) -> str:
    """The message of a user error of `wrsim argv`: exit status 2, one `wrsim: error:` line, no traceback."""
    code = cli.main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("wrsim: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    return err[len("wrsim: error: ") : -1]


def write_certificates(security: Security, folder: Path) -> list[str]:
    """The CA, certificate and key of a Security.temporary() as PEM files: the options naming them."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "ca.pem").write_text(security.tls_ca_file)  # self-signed: the certificate is its own CA
    (folder / "key.pem").write_text(security.tls_client_key)
    ca, key = str(folder / "ca.pem"), str(folder / "key.pem")
    return ["--tls-ca-file", ca, "--tls-cert", ca, "--tls-key", key]


def quiet_cluster(**kwargs) -> LocalCluster:
    """One single-threaded worker in this process: its tasks run here, its address is a loopback one."""
    return LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=False,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
        **kwargs,
    )


@pytest.fixture(scope="module")
def tls_cluster(tmp_path_factory):
    """A TLS LocalCluster with temporary certificates, and the options that name them."""
    security = Security.temporary()
    with quiet_cluster(security=security, protocol="tls://") as c:
        yield c, write_certificates(security, tmp_path_factory.mktemp("certs"))


@pytest.fixture
def no_client(monkeypatch):
    """distributed.Client made to fail the test: what is refused must be refused before any connection."""

    def connecting(*args, **kwargs):
        raise AssertionError(f"Client{args} was called")

    monkeypatch.setattr(distributed, "Client", connecting)


def test_a_study_on_a_tls_cluster_gives_the_local_result(tls_cluster, tmp_path, capsys):
    c, options = tls_cluster
    assert c.scheduler_address.startswith("tls://")
    code = cli.main([*STUDY, "--results", str(tmp_path), "--scheduler", c.scheduler_address, *options])
    out = capsys.readouterr().out
    assert code == 0 and "2 samples, 0 failed" in out, out

    spec = StudySpec("stroke", ("tolerances/production",), samples=2, stop=0.5)
    study, _ = read_study(spec, tmp_path)
    assert sorted(study.rows) == [0, 1]
    here = f"{socket.gethostname()}:{os.getpid()}"
    assert {r["worker"] for r in study.rows.values()} == {here}  # the cluster's worker ran them (a pool: other pids)
    base, _ = study_params(spec)
    fs = factors(base)
    for i, row in study.rows.items():
        values = draw(fs, spec.seed, i)
        task = Task("stroke", i, row["label"], values, sample_set(base, values, row["label"]), stop=0.5)
        local = run_sample(dataclasses.replace(task, workdir=str(tmp_path / "local")))
        assert not local.error and local.outputs
        assert {o.name: o.value for o in local.outputs} == row["outputs"]  # identical, not close


def test_a_plain_tcp_scheduler_on_this_machine_is_allowed():
    with quiet_cluster(protocol="tcp://") as c:
        port = c.scheduler_address.rsplit(":", 1)[1]
        for address in (c.scheduler_address, f"tcp://localhost:{port}", f"127.0.0.1:{port}"):
            with cluster.connect(address, {}) as client:
                cluster.check_workers(client)  # this machine's workers have this machine's environment
                assert client.submit(sum, [1, 2]).result() == 3


@pytest.mark.parametrize(
    "address", ["tcp://192.0.2.1:8786", "192.0.2.1:8786", "tcp://scheduler.example.com:8786", "ws://[2001:db8::1]:80"]
)
def test_a_plain_address_to_another_machine_is_refused_before_connecting(no_client, capsys, address):
    message = one_error(capsys, [*STUDY, "--scheduler", address])
    assert message.startswith(f"--scheduler {address}: refused, Dask sends its tasks as pickled code")
    assert "tls://" in message and "--insecure" in message


def test_with_insecure_an_unreachable_plain_address_is_the_cannot_reach_error(capsys, tmp_path):
    with dask.config.set({"distributed.comm.timeouts.connect": "0.5s"}):
        message = one_error(
            capsys, [*STUDY, "--results", str(tmp_path), "--scheduler", "tcp://192.0.2.1:8786", "--insecure"]
        )
    assert message.startswith("--scheduler tcp://192.0.2.1:8786: cannot reach the Dask scheduler (")


def test_tls_options_need_a_tls_scheduler(no_client, capsys, tmp_path):
    assert one_error(capsys, [*STUDY, "--scheduler", "tcp://127.0.0.1:8786", "--tls-cert", "c.pem"]) == (
        "--tls-cert is for a tls:// scheduler, and --scheduler tcp://127.0.0.1:8786 is plain tcp://"
    )
    assert one_error(capsys, [*STUDY, "--insecure"]) == (
        "--insecure goes with --scheduler (a Dask scheduler on another machine)"
    )


def test_a_missing_or_unreadable_certificate_is_one_error_naming_it(no_client, capsys, tmp_path):
    options = write_certificates(Security.temporary(), tmp_path)
    ca = options[1]
    tls = [*STUDY, "--scheduler", "tls://192.0.2.1:8786"]
    missing = str(tmp_path / "missing.pem")
    assert one_error(capsys, [*tls, *options, "--tls-cert", missing]) == (
        f"--tls-cert {missing}: cannot read it (No such file or directory)"
    )
    message = one_error(capsys, [*tls, *options, "--tls-key", ca])  # a certificate where the key belongs
    assert message.startswith(f"--tls-ca-file {ca}, --tls-cert {ca}, --tls-key {ca}: not a PEM CA certificate")
    with dask.config.set({"distributed.comm.tls.ca-file": missing}):  # from the Dask config when no option
        assert one_error(capsys, [*tls, *options[2:]]) == (
            f"distributed.comm.tls.ca-file (Dask config) {missing}: cannot read it (No such file or directory)"
        )
    assert one_error(capsys, tls) == (
        "a tls:// scheduler needs --tls-ca-file or the Dask config distributed.comm.tls.ca-file: neither is set"
    )


def test_a_failed_handshake_is_one_error_naming_the_address(tls_cluster, capsys, tmp_path):
    c, options = tls_cluster
    strangers = write_certificates(Security.temporary(), tmp_path)  # a CA the cluster's certificate is not from
    message = one_error(capsys, [*STUDY, "--scheduler", c.scheduler_address, *strangers])
    assert message.startswith(
        f"--scheduler {c.scheduler_address}: the TLS handshake with the scheduler failed: its certificate is not "
        f"signed by the CA {strangers[1]} ("
    )
    # the cluster's CA, but this client's certificate is one the scheduler does not trust
    message = one_error(capsys, [*STUDY, "--scheduler", c.scheduler_address, *options[:2], *strangers[2:]])
    assert message.startswith(f"--scheduler {c.scheduler_address}: the TLS handshake with the scheduler failed (")
    assert message.endswith(f"trusts the certificate {strangers[3]}?")


def test_the_environment_is_this_machines_simulators_and_model_library():
    from wrsim.backend import ghdl
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.study.engine import library_digest

    assert cluster.environment() == {
        "ngspice": NgspiceBatch().check().removeprefix("ngspice-"),
        "GHDL": ghdl.check().removeprefix("GHDL "),
        "model library": library_digest(),
    }
    assert cluster.environment()["ngspice"].isdigit()


def older_ngspice() -> dict[str, str]:
    return {**cluster.environment(), "ngspice": "45"}


def without_wrsim() -> dict[str, str]:
    raise ModuleNotFoundError("No module named 'wrsim'")


@pytest.mark.parametrize(
    "on_worker, difference",
    [
        (older_ngspice, "ngspice 45 (here {ngspice})"),
        (without_wrsim, "cannot tell its environment (ModuleNotFoundError: No module named 'wrsim')"),
    ],
)
def test_a_worker_whose_environment_differs_is_one_error_naming_it(
    tls_cluster, monkeypatch, capsys, tmp_path, on_worker, difference
):
    c, options = tls_cluster
    monkeypatch.setattr(cluster, "worker_environment", on_worker)  # what Client.run sends to the workers
    message = one_error(capsys, [*STUDY, "--results", str(tmp_path), "--scheduler", c.scheduler_address, *options])
    (worker,) = c.scheduler.workers
    assert message == (
        f"worker {worker}: {difference.format(**cluster.environment())}: run the workers with this machine's wrsim "
        "checkout and simulators"
    )
    assert not (tmp_path / "study").exists()  # before the first task
