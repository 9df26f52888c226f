"""The HTML report checked in a real browser: each page is opened in headless Chromium (Debian package `chromium`),
rendered to a PNG and checked for JavaScript errors, resources that failed to load, broken images and links to
local files that do not exist.

Chromium is driven over the DevTools protocol through `--remote-debugging-pipe`: it reads commands from its file
descriptor 3 and writes answers and events to its descriptor 4, each a JSON object ended by a NUL byte. One browser
serves all pages of a call; each page gets its own tab (target), attached in flat mode, so its events carry the
tab's session id.
"""

from __future__ import annotations

import base64
import contextlib
import json
import os
import select
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit, urlunsplit
from urllib.request import url2pathname

from wrsim.errors import WrsimError

__all__ = ["CHROMIUM", "check_pages", "find_chromium", "probe_plot"]

CHROMIUM = "chromium"  # the Debian package and its command

_WINDOW = (1280, 900)  # CSS pixels; the screenshot covers the whole page, however long
_MAX_SHOT_HEIGHT = 16384  # CSS pixels; longer pages are cut
_SETTLE = 0.2  # s after the load event for late errors (timers, promise rejections)
_CLOSE_TIMEOUT = 5.0  # s for the browser to exit after Browser.close

# Evaluated in the page after its load event: the images that did not load and the targets of all links.
_PAGE_CHECK_JS = """(() => ({
  images: Array.from(document.images)
    .filter(i => !i.complete || i.naturalWidth === 0)
    .map(i => ({src: i.getAttribute('src') || '', url: i.currentSrc || i.src || ''})),
  links: Array.from(document.querySelectorAll('a[href], area[href]'))
    .map(a => ({href: a.getAttribute('href') || '', url: a.href})),
}))()"""


class _Timeout(Exception):
    """The browser did not answer in time."""


def find_chromium() -> str:
    """The path of the `chromium` command; WrsimError saying what to install when it is not on PATH."""
    path = shutil.which(CHROMIUM)
    if path is None:
        raise WrsimError(
            f"'{CHROMIUM}' not found on PATH: the browser check of the HTML report needs headless "
            f"Chromium; install it with 'make setup' (or 'apt-get install --no-install-recommends "
            f"{CHROMIUM}' on Debian 12)"
        )
    return path


def check_pages(pages: list[Path], screenshots: Path, timeout: float = 60.0) -> list[str]:
    """Open each of `pages` (local HTML files) in headless Chromium, write its rendering to
    `screenshots/<page-stem>.png` and return the problems found, one line each, starting with the page's path;
    an empty list means every page is fine.

    Problems: an uncaught JavaScript exception, a console error (console.error, a failed console.assert), an error
    logged by the browser, a resource that failed to load (image, stylesheet, script, ...: e.g.
    net::ERR_FILE_NOT_FOUND), an <img> that is not complete or has naturalWidth 0, and a link (<a href>) to a local
    file that does not exist relative to the page (http(s), mailto and other non-file links and '#' anchors are
    not followed). A missing file is reported once even when it is both loaded and linked.

    Two pages with the same stem get distinct screenshots: the later one is named `<parent>-<stem>.png` (or
    numbered). `timeout` [s] bounds each page (and the browser's start); a page that does not load in time is a
    problem, and the browser is restarted for the pages after it. Raises WrsimError when Chromium is not installed
    or does not start or answer.
    """
    chromium = find_chromium()
    screenshots = Path(screenshots)
    screenshots.mkdir(parents=True, exist_ok=True)
    problems: list[str] = []
    names: set[str] = set()
    browser: _Browser | None = None
    try:
        for page in pages:
            page = Path(page)
            shot = screenshots / _screenshot_name(page, names)
            if not page.is_file():
                problems.append(f"{page}: page does not exist")
                continue
            if browser is None:
                browser = _Browser(chromium, timeout)
            try:
                problems.extend(f"{page}: {p}" for p in browser.check(page, shot, timeout))
            except _Timeout as e:
                problems.append(f"{page}: {e}")
                browser.close()
                browser = None
    finally:
        if browser is not None:
            browser.close()
    return problems


# The plot area of a plotly.js figure in page coordinates, its x range, and (with a data x) that x's page position.
_PLOT_AREA_JS = """(() => {{
  const d = document.getElementById({element}), f = d._fullLayout, r = d.getBoundingClientRect();
  return {{left: r.left + f._size.l, top: r.top + f._size.t, width: f._size.w, height: f._size.h,
          range: f.xaxis.range.slice(), at: {x} === null ? null : r.left + f._size.l + f.xaxis.d2p({x})}};
}})()"""


def probe_plot(page: Path, element: str, zoom: tuple[float, float], cursor: float, timeout: float = 60.0) -> dict:
    """Use the interactive plot `element` of `page` as an engineer does, with the browser's own mouse events: drag
    across the plot area at half its height from the fraction zoom[0] to zoom[1] of its width (a box zoom on x),
    then rest the mouse at x = `cursor` (data units). Returns {"before": x range, "after": x range after the zoom,
    "cursor": the text of the cursor's label}. Raises WrsimError when the page or the plot does not work."""
    browser = _Browser(find_chromium(), timeout)
    try:
        with browser.tab(timeout) as (session, left):
            error = browser.load(session, Path(page), time.monotonic() + left(), left)
            if error:
                raise WrsimError(f"{page}: cannot open the page: {error}")
            area = browser.evaluate(session, _PLOT_AREA_JS.format(element=json.dumps(element), x="null"), left)
            y = area["top"] + area["height"] / 2
            start, end = (area["left"] + f * area["width"] for f in zoom)
            browser.mouse(session, "mouseMoved", start, y, left, pressed=False)
            browser.mouse(session, "mousePressed", start, y, left, pressed=True)
            for k in range(1, 11):  # a drag in steps, as a hand moves
                browser.mouse(session, "mouseMoved", start + (end - start) * k / 10, y, left, pressed=True)
            browser.mouse(session, "mouseReleased", end, y, left, pressed=True)
            browser.pump(time.monotonic() + 0.5)  # the relayout
            after = browser.evaluate(session, _PLOT_AREA_JS.format(element=json.dumps(element), x=cursor), left)
            browser.mouse(session, "mouseMoved", after["at"], y, left, pressed=False)
            browser.pump(time.monotonic() + 0.5)  # the hover label
            label = browser.evaluate(
                session,
                f"document.getElementById({json.dumps(element)}).querySelector('.hoverlayer').textContent",
                left,
            )
            browser.take_events(session)
            return {"before": area["range"], "after": after["range"], "cursor": label}
    except _Timeout as e:
        raise WrsimError(f"{page}: {e}") from None
    finally:
        browser.close()


def _screenshot_name(page: Path, used: set[str]) -> str:
    candidates = [page.stem, f"{page.parent.name}-{page.stem}" if page.parent.name else page.stem]
    candidates += [f"{page.stem}-{i}" for i in range(2, len(used) + 3)]
    name = next(c for c in candidates if c not in used)
    used.add(name)
    return f"{name}.png"


class _Browser:
    """A headless Chromium process and its DevTools pipe."""

    def __init__(self, chromium: str, timeout: float):
        self._profile = tempfile.TemporaryDirectory(prefix="wrsim-chromium-")
        self._stderr = tempfile.TemporaryFile()
        self._buffer = b""
        self._next_id = 0
        self._events: list[dict[str, Any]] = []
        args = [
            chromium,
            "--headless",
            "--remote-debugging-pipe",
            "--disable-gpu",
            "--disable-dev-shm-usage",
            f"--user-data-dir={self._profile.name}",
            f"--window-size={_WINDOW[0]},{_WINDOW[1]}",
            "--no-first-run",
            "--no-default-browser-check",
            "--disable-extensions",
            "--disable-sync",
            "--disable-background-networking",
            "--disable-component-update",
            "--hide-scrollbars",
            "--mute-audio",
            "--password-store=basic",
            "about:blank",
        ]
        if os.geteuid() == 0:
            args.insert(1, "--no-sandbox")  # Chromium refuses to run as root with its sandbox
        to_child, self._write_fd = os.pipe()
        self._read_fd, from_child = os.pipe()
        try:
            self._proc = subprocess.Popen(
                args,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=self._stderr,
                pass_fds=(3, 4),
                preexec_fn=_pipe_fds(to_child, from_child),
                start_new_session=True,
            )
        except OSError as e:
            os.close(self._write_fd)
            os.close(self._read_fd)
            self._stderr.close()
            self._profile.cleanup()
            raise WrsimError(f"cannot start {chromium}: {e}") from e
        finally:
            os.close(to_child)
            os.close(from_child)
        try:
            self.call("Browser.getVersion", timeout=timeout)
        except (_Timeout, WrsimError) as e:
            self.close()
            raise WrsimError(f"headless {chromium} did not start: {e}") from e

    # --- the protocol ---

    def send(self, method: str, params: dict[str, Any] | None = None, session: str | None = None) -> int:
        """Send a command; returns its id."""
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if session is not None:
            message["sessionId"] = session
        data = json.dumps(message).encode() + b"\0"
        try:
            while data:
                data = data[os.write(self._write_fd, data) :]
        except OSError as e:
            raise WrsimError(f"the browser closed its DevTools pipe{self._stderr_tail()}") from e
        return self._next_id

    def call(
        self, method: str, params: dict[str, Any] | None = None, session: str | None = None, timeout: float = 30.0
    ) -> dict[str, Any]:
        """Send a command and wait for its result; events that arrive meanwhile are kept for `wait_for`."""
        cid = self.send(method, params, session)
        deadline = time.monotonic() + timeout
        while True:
            message = self._receive(deadline, f"no answer to {method} within {timeout:g} s")
            if message.get("id") == cid:
                if "error" in message:
                    raise WrsimError(f"{method} failed: {message['error'].get('message', message['error'])}")
                result: dict[str, Any] = message.get("result", {})
                return result
            if "method" in message:
                self._events.append(message)

    def pump(self, deadline: float, until: Callable[[dict[str, Any]], bool] | None = None, what: str = "") -> None:
        """Collect events until one satisfies `until` (_Timeout at `deadline`), or, without `until`, until
        `deadline`."""
        if until is not None and any(until(e) for e in self._events):
            return
        while True:
            try:
                message = self._receive(deadline, what)
            except _Timeout:
                if until is None:
                    return
                raise
            if "method" in message:
                self._events.append(message)
                if until is not None and until(message):
                    return

    def take_events(self, session: str) -> list[dict[str, Any]]:
        """The events of `session` received so far, removed from the queue (other sessions' are dropped)."""
        events = [e for e in self._events if e.get("sessionId") == session]
        self._events = []
        return events

    def _receive(self, deadline: float, what: str) -> dict[str, Any]:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._read_fd], [], [], left)[0]:
                raise _Timeout(what)
            chunk = os.read(self._read_fd, 1 << 20)
            if not chunk:
                raise WrsimError(f"the browser closed its DevTools pipe{self._stderr_tail()}")
            self._buffer += chunk
        raw, self._buffer = self._buffer.split(b"\0", 1)
        message: dict[str, Any] = json.loads(raw)
        return message

    def _stderr_tail(self) -> str:
        self._stderr.seek(0)
        lines = self._stderr.read().decode(errors="replace").strip().splitlines()[-5:]
        status = self._proc.poll() if hasattr(self, "_proc") else None
        exited = f" (it exited with status {status})" if status is not None else ""
        return exited + ("; its last output: " + " | ".join(lines) if lines else "")

    def close(self) -> None:
        """Close the browser (killing it if it does not exit) and remove its profile."""
        try:
            if self._proc.poll() is None:
                try:
                    self.send("Browser.close")
                except WrsimError:
                    pass
                try:
                    self._proc.wait(_CLOSE_TIMEOUT)
                except subprocess.TimeoutExpired:
                    os.killpg(self._proc.pid, signal.SIGKILL)  # its own process group (start_new_session)
                    self._proc.wait()
        finally:
            for fd in (self._write_fd, self._read_fd):
                try:
                    os.close(fd)
                except OSError:
                    pass
            self._stderr.close()
            self._profile.cleanup()

    # --- one page ---

    @contextlib.contextmanager
    def tab(self, timeout: float) -> Iterator[tuple[str, Callable[[], float]]]:
        """A new tab attached in flat mode: its session id and the seconds left of `timeout`; closed at the end."""
        deadline = time.monotonic() + timeout
        left = lambda: max(deadline - time.monotonic(), 0.001)  # noqa: E731
        target = self.call("Target.createTarget", {"url": "about:blank"}, timeout=left())["targetId"]
        session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True}, timeout=left())["sessionId"]
        try:
            yield session, left
        finally:
            try:
                self.call("Target.closeTarget", {"targetId": target}, timeout=min(left(), _CLOSE_TIMEOUT))
            except (_Timeout, WrsimError):
                pass

    def evaluate(self, session: str, expression: str, left: Callable[[], float]) -> Any:
        """The value of a JavaScript expression in the tab (awaited when it is a promise)."""
        answer = self.call(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
            session=session,
            timeout=left(),
        )
        if "exceptionDetails" in answer:
            raise WrsimError(f"the page's script failed: {_remote_text(answer['exceptionDetails'])}")
        return answer.get("result", {}).get("value")

    def mouse(self, session: str, kind: str, x: float, y: float, left: Callable[[], float], pressed: bool) -> None:
        """One mouse event at page coordinates (x, y): kind mousePressed, mouseMoved or mouseReleased."""
        params: dict[str, Any] = {"type": kind, "x": x, "y": y, "button": "left" if pressed else "none"}
        params["buttons"] = 1 if pressed and kind != "mouseReleased" else 0
        if kind != "mouseMoved":
            params["clickCount"] = 1
        self.call("Input.dispatchMouseEvent", params, session=session, timeout=left())

    def check(self, page: Path, shot: Path, timeout: float) -> list[str]:
        """Load `page` in a new tab, write its screenshot to `shot`; the problems found (without the page's name)."""
        deadline = time.monotonic() + timeout
        with self.tab(timeout) as (session, left):
            error = self.load(session, page, deadline, left)
            if error:  # no load event follows; the screenshot shows the browser's error page
                self._screenshot(session, shot, left)
                return [f"cannot open the page: {error}"]
            checks = self.call(
                "Runtime.evaluate",
                {"expression": _PAGE_CHECK_JS, "returnByValue": True},
                session=session,
                timeout=left(),
            )
            problems = _problems(page, self.take_events(session), checks)
            self._screenshot(session, shot, left)
            return problems

    def load(self, session: str, page: Path, deadline: float, left: Callable[[], float]) -> str | None:
        """Open `page` in the tab and wait for its load event and a moment after it (late errors); the browser's
        error text when it cannot open the page."""
        for domain in ("Runtime", "Log", "Page", "Network"):
            self.call(f"{domain}.enable", session=session, timeout=left())
        self.call("Page.setLifecycleEventsEnabled", {"enabled": True}, session=session, timeout=left())
        self.call(
            "Emulation.setDeviceMetricsOverride",
            {"width": _WINDOW[0], "height": _WINDOW[1], "deviceScaleFactor": 1, "mobile": False},
            session=session,
            timeout=left(),
        )
        self.take_events(session)  # anything about about:blank
        nav = self.call("Page.navigate", {"url": _absolute(page).as_uri()}, session=session, timeout=left())
        if nav.get("errorText"):
            self.pump(min(deadline, time.monotonic() + _SETTLE))
            return str(nav["errorText"])
        loader = nav.get("loaderId")

        def loaded(e: dict[str, Any]) -> bool:
            return (
                e.get("sessionId") == session
                and e.get("method") == "Page.lifecycleEvent"
                and e["params"].get("name") == "load"
                and e["params"].get("loaderId") == loader
            )

        self.pump(deadline, loaded, f"the page did not finish loading within {deadline - time.monotonic():.0f} s")
        self.pump(min(deadline, time.monotonic() + _SETTLE))
        return None

    def _screenshot(self, session: str, shot: Path, left: Callable[[], float]) -> None:
        size = self.call("Page.getLayoutMetrics", session=session, timeout=left()).get("cssContentSize", {})
        width = max(int(size.get("width", _WINDOW[0])), 1)
        height = min(max(int(size.get("height", _WINDOW[1])), 1), _MAX_SHOT_HEIGHT)
        png = self.call(
            "Page.captureScreenshot",
            {
                "format": "png",
                "captureBeyondViewport": True,
                "clip": {"x": 0, "y": 0, "width": width, "height": height, "scale": 1},
            },
            session=session,
            timeout=left(),
        )["data"]
        shot.write_bytes(base64.b64decode(png))


def _pipe_fds(to_child: int, from_child: int) -> Callable[[], None]:
    """A preexec_fn placing the DevTools pipe on the child's descriptors 3 (commands) and 4 (answers)."""

    def place() -> None:
        read, write = os.dup(to_child), os.dup(from_child)  # out of the way of 3 and 4
        os.dup2(read, 3)
        os.dup2(write, 4)
        os.close(read)
        os.close(write)

    return place


def _problems(page: Path, events: list[dict[str, Any]], checks: dict[str, Any]) -> list[str]:
    """The problems of one page from its DevTools events and the result of _PAGE_CHECK_JS."""
    problems: list[str] = []
    urls: dict[str, str] = {}
    failed: set[str] = set()  # resource URLs (without fragment) already reported
    logged: list[tuple[str, str]] = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Network.requestWillBeSent":
            urls[params["requestId"]] = params["request"]["url"]
        elif method == "Network.loadingFailed":
            url = urls.get(params.get("requestId", ""), "")
            failed.add(_bare(url))
            kind = str(params.get("type") or "resource").lower()
            reason = params.get("errorText") or params.get("blockedReason") or "failed"
            problems.append(f"{kind} {_show(page, url)} failed to load: {reason}")
        elif method == "Runtime.exceptionThrown":
            problems.append(f"JavaScript exception: {_exception_text(params.get('exceptionDetails', {}), page)}")
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            args = " ".join(_remote_text(a) for a in params.get("args", []))
            problems.append(f"console.{params['type']}: {args}{_where(params.get('stackTrace'), page)}")
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            entry = params["entry"]
            logged.append(
                (entry.get("url") or "", f"browser error ({entry.get('source', '?')}): {entry.get('text', '')}")
            )
    for url, text in logged:  # "Failed to load resource" entries repeat Network.loadingFailed
        if not (url and _bare(url) in failed):
            problems.append(text + (f" ({_show(page, url)})" if url else ""))
    value = checks.get("result", {}).get("value") or {}
    if checks.get("exceptionDetails"):
        problems.append(f"the page check script failed: {_exception_text(checks['exceptionDetails'], page)}")
    for image in value.get("images", []):
        if _bare(image["url"]) not in failed:
            failed.add(_bare(image["url"]))
            problems.append(f"image {image['src'] or '(no src)'} did not load (not complete or naturalWidth 0)")
    for link in value.get("links", []):
        href, url = link["href"], link["url"]
        parts = urlsplit(url)
        if href.startswith("#") or parts.scheme != "file":
            continue
        target = Path(url2pathname(parts.path))
        if not target.exists() and _bare(url) not in failed:
            failed.add(_bare(url))
            shown = _show(page, url)
            problems.append(f"broken link {href}: no such file" + ("" if shown == href else f" ({shown})"))
    return [" ".join(p.split()) for p in problems]  # one line each


def _absolute(page: Path) -> Path:
    """`page` made absolute without resolving symbolic links: relative links of a page in a published result
    folder (a link to a version folder) are meant relative to the link, as a browser that opened it would."""
    return Path(os.path.abspath(page))


def _bare(url: str) -> str:
    parts = urlsplit(url)
    return urlunsplit((parts.scheme, parts.netloc, parts.path, "", ""))


def _show(page: Path, url: str) -> str:
    """A file URL as a path relative to the page's folder; other URLs as they are."""
    parts = urlsplit(url)
    if parts.scheme != "file":
        return url or "(unknown URL)"
    return os.path.relpath(url2pathname(parts.path), _absolute(page).parent)


def _where(stack: dict[str, Any] | None, page: Path) -> str:
    frames = (stack or {}).get("callFrames") or []
    if not frames:
        return ""
    f = frames[0]
    return f" ({_show(page, f.get('url', ''))}:{f.get('lineNumber', 0) + 1})"


def _exception_text(details: dict[str, Any], page: Path) -> str:
    exception = details.get("exception") or {}
    text = (exception.get("description") or "").split("\n")[0] or _remote_text(exception)
    prefix = details.get("text") or "Uncaught"
    message = f"{prefix} {text}" if text and text not in prefix else prefix
    url = details.get("url") or ""
    where = f" ({_show(page, url)}:{details.get('lineNumber', 0) + 1})" if url else ""
    return message + where


def _remote_text(obj: dict[str, Any]) -> str:
    """A DevTools RemoteObject as text."""
    if "value" in obj:
        return str(obj["value"])
    return str(obj.get("description") or obj.get("unserializableValue") or obj.get("type", ""))
