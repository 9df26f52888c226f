"""Connecting to a Dask scheduler (`wrsim study --scheduler`, `wrsim score --fleet --scheduler`) without trusting
the network, and checking its workers before the first task.

Dask's tasks are pickled Python: whoever can talk to the scheduler or read the channel runs code on the workers or
sees it. So a `tls://` (or `wss://`) address is connected with Dask's TLS settings — the CA, the client certificate
and its key from `--tls-ca-file`, `--tls-cert` and `--tls-key`, else from the Dask config
(`distributed.comm.tls.ca-file`, `distributed.comm.tls.client.cert`, `distributed.comm.tls.client.key`, which
`distributed.Security` reads) — and a plain `tcp://` (or schemeless) address is refused unless it is this machine's
loopback (127.0.0.0/8, ::1, localhost) or the user passes `--insecure`.

Once connected, `check_workers` asks every worker (`Client.run`) for what its results depend on — the ngspice and
GHDL versions wrsim finds there and the digest of the model library — and compares them with this machine's."""

from __future__ import annotations

import functools
import ipaddress
import ssl
from collections.abc import Callable
from typing import Any

from wrsim.errors import WrsimError

__all__ = ["ENCRYPTED", "TLS_OPTIONS", "connect", "check_workers", "environment", "worker_environment"]

ENCRYPTED = ("tls", "wss")  # Dask's schemes that carry TLS, with the certificates of `distributed.Security`

# the TLS settings of a client: distributed.Security's field, wrsim's option, the Dask config key it defaults to
TLS_OPTIONS = (
    ("tls_ca_file", "--tls-ca-file", "distributed.comm.tls.ca-file"),
    ("tls_client_cert", "--tls-cert", "distributed.comm.tls.client.cert"),
    ("tls_client_key", "--tls-key", "distributed.comm.tls.client.key"),
)


def connect(address: str, tls: dict[str, str | None], insecure: bool = False) -> Any:
    """A Dask client of the scheduler at `address`. `tls`: the files the options name, by Security field
    (tls_ca_file, tls_client_cert, tls_client_key; None or missing: the Dask config's). A plain address to
    another machine is refused unless `insecure`; every failure (a certificate that cannot be read, a handshake
    the scheduler or this client rejects, a scheduler not reached) is one WrsimError, raised before any task."""
    from distributed import Client
    from distributed.comm.addressing import parse_address, parse_host_port

    given = {field: value for field, value in tls.items() if value}
    try:
        scheme, location = parse_address(address, strict=False)
        host, _ = parse_host_port(location)
    except ValueError as e:  # as Client would say, before it connects
        raise WrsimError(f"--scheduler {address}: cannot reach the Dask scheduler ({e})") from None
    if scheme in ENCRYPTED:
        security = _security(given)
    elif given:
        flag = next(f for field, f, _ in TLS_OPTIONS if field in given)
        raise WrsimError(f"{flag} is for a tls:// scheduler, and --scheduler {address} is plain {scheme}://")
    elif not (insecure or _loopback(host)):
        raise WrsimError(
            f"--scheduler {address}: refused, Dask sends its tasks as pickled code and a plain {scheme}:// "
            "connection to another machine is neither encrypted nor authenticated (anyone on the path can read "
            "them or run code on the workers); use a tls:// address with certificates (--tls-ca-file, --tls-cert, "
            "--tls-key or the Dask config distributed.comm.tls.*) or, on a network you trust, pass --insecure"
        )
    else:
        security = None
    try:
        return Client(address, security=security)  # its timeout: Dask's distributed.comm.timeouts.connect (30 s)
    except (OSError, ValueError) as e:
        handshake = _ssl_cause(e)
        if handshake is None or security is None:
            raise WrsimError(f"--scheduler {address}: cannot reach the Dask scheduler ({e})") from None
        if isinstance(handshake, ssl.SSLCertVerificationError):
            ca = _shown(security.tls_ca_file)
            why = f": its certificate is not signed by the CA {ca} ({handshake.verify_message})"
        else:
            why = (
                f" ({handshake.reason or handshake}): is it a TLS scheduler that trusts the certificate "
                f"{_shown(security.tls_client_cert)}?"
            )
        raise WrsimError(f"--scheduler {address}: the TLS handshake with the scheduler failed{why}") from None


def _security(given: dict[str, str]) -> Any:
    """Dask's Security for a TLS client: the options' files over the Dask config's, each checked readable and the
    three checked to be a CA certificate, a certificate and its key (one WrsimError naming the files)."""
    from distributed import Security

    security = Security(require_encryption=True, **given)
    sources = []
    for field, flag, key in TLS_OPTIONS:
        value = getattr(security, field)
        source = flag if field in given else f"{key} (Dask config)"
        if value is None:
            if field == "tls_client_key":  # the key may follow the certificate in its file
                continue
            raise WrsimError(f"a tls:// scheduler needs {flag} or the Dask config {key}: neither is set")
        if _shown(value) == value:  # a file (Dask also takes the PEM text itself)
            try:
                with open(value, "rb") as f:
                    f.read(1)
            except OSError as e:
                raise WrsimError(f"{source} {value}: cannot read it ({e.strerror})") from None
        sources.append(f"{source} {_shown(value)}")
    try:
        security.get_connection_args("client")  # loads the CA, the certificate and its key
    except (ssl.SSLError, ValueError) as e:
        raise WrsimError(
            f"{', '.join(sources)}: not a PEM CA certificate and a PEM certificate with its private key ({e})"
        ) from None
    return security


def _shown(value: str) -> str:
    """A TLS setting as a message names it: its file, or '(PEM text)' for the certificate or key itself."""
    return "(PEM text)" if "\n" in value else value


def _loopback(host: str) -> bool:
    """Whether `host` is this machine's loopback: localhost or an address in 127.0.0.0/8 or ::1 (names are not
    resolved: a name could point anywhere)."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _ssl_cause(e: BaseException) -> ssl.SSLError | None:
    """The TLS error behind a failed connection, if any: Dask wraps it in a CommClosedError (as its cause, or as the
    `real_error` of the Tornado StreamClosedError it handled)."""
    seen: BaseException | None = e
    while seen is not None:
        if isinstance(seen, ssl.SSLError):
            return seen
        seen = seen.__cause__ or getattr(seen, "real_error", None) or seen.__context__
    return None


def _tool(check: Callable[[], str], prefix: str) -> str:
    """A tool's version as `check` (a backend's, raising WrsimError when it is missing) gives it, without
    `prefix`; 'unusable (why)' when the check fails."""
    try:
        return check().removeprefix(prefix)
    except WrsimError as e:
        return f"unusable ({e})"


@functools.cache
def environment() -> dict[str, str]:
    """What a sample's result depends on in this process, computed once: the ngspice and GHDL versions wrsim finds
    and the digest of the model library (paths.LIBRARY: the VHDL and C files of vhdl/ and testbenches/)."""
    from wrsim.backend import ghdl
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.study.engine import library_digest

    return {
        "ngspice": _tool(NgspiceBatch().check, "ngspice-"),
        "GHDL": _tool(ghdl.check, "GHDL "),
        "model library": library_digest(),
    }


def worker_environment() -> dict[str, str]:
    """The function `check_workers` runs on every worker: that worker's `environment()`."""
    return environment()


def check_workers(client: Any) -> None:
    """Compare every worker's environment with this machine's; one WrsimError naming the first worker that differs
    and what differs ('worker tls://10.0.0.5:40123: ngspice 45 (here 46)'), and how many others do. Workers
    that join later are not asked (a sample still checks the model library's digest where it runs)."""
    here = environment()
    answers = client.run(worker_environment, on_error="return")
    problems = []
    for worker, there in sorted(answers.items()):
        if isinstance(there, BaseException):  # e.g. a worker without wrsim: No module named 'wrsim'
            problems.append(f"worker {worker}: cannot tell its environment ({type(there).__name__}: {there})")
            continue
        differ = [
            f"{what} {there.get(what, 'unknown')} (here {value})"
            for what, value in here.items()
            if there.get(what) != value
        ]
        if differ:
            problems.append(f"worker {worker}: {'; '.join(differ)}")
    if problems:
        others = len(problems) - 1
        others_text = f" (and {others} other worker{'s' if others > 1 else ''})" if others else ""
        raise WrsimError(
            f"{problems[0]}{others_text}: run the workers with this machine's wrsim checkout and simulators"
        )
