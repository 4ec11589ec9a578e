"""Screenshots of the scene viewer: docs/viewer_room.png (one room's scene.html) and
docs/viewer_gallery.png (index.html of a folder of ~6 scenes), 1280 x 800.

    python benchmarks/viewer_shots.py [--scenes DIR] [--docs docs]

Generates bedroom, living_room and kitchen scenes with ``pair2scene generate`` (into
``--scenes``, a temporary folder by default), writes each folder's scene.html (embedding
the scene.glb the run wrote) and the folder's index.html, then loads them in headless
Chromium (Debian: ``apt-get install -y chromium``) and saves the screenshots.

:class:`Chromium` is also what tests/io/test_viewer_page.py drives pages with: the Chrome
DevTools protocol over ``--remote-debugging-pipe`` (NUL-terminated JSON messages on file
descriptors 3 and 4), standard library only.
"""

from __future__ import annotations

import argparse
import base64
import fcntl
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
WIDTH, HEIGHT = 1280, 800
ROOMS = (("bedroom", 2, 0), ("living_room", 2, 0), ("kitchen", 2, 0))
"""(room type, scenes, first seed) of the gallery; the room shot is the first bedroom."""
GALLERY_READY = (
    "document.readyState === 'complete' && Array.from(document.images)"
    ".filter(i => i.getBoundingClientRect().top < innerHeight).every(i => i.complete)"
)
"""The gallery is drawn: the thumbnails in view are loaded (they load lazily)."""


def find_chromium() -> str | None:
    """The first Chromium-like browser on PATH (CHROMIUM overrides), or None."""
    if os.environ.get("CHROMIUM"):
        return shutil.which(os.environ["CHROMIUM"])
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


class CdpError(RuntimeError):
    pass


_EXEC_WITH_FDS = (
    "import os, sys; r, w = map(int, sys.argv[1:3]); os.dup2(r, 3); os.dup2(w, 4); "
    "os.close(r); os.close(w); os.execv(sys.argv[3], sys.argv[3:])"
)
"""Run argv[3:] with fd argv[1] as its fd 3 and fd argv[2] as its fd 4 (both above 9)."""


def _high_fd(fd: int) -> int:
    """A duplicate of ``fd`` numbered 10 or more (``fd`` is closed)."""
    high = fcntl.fcntl(fd, fcntl.F_DUPFD, 10)
    os.close(fd)
    return high


class Chromium:
    """A headless Chromium and one page in it, driven over the DevTools protocol.

    WebGL comes from SwiftShader (software; ``--enable-unsafe-swiftshader``), so it works
    without a GPU or a display. As root, Chromium needs ``--no-sandbox``.
    Use as a context manager; :meth:`open` loads a page and waits for it to be ready,
    :attr:`errors` collects console errors, uncaught exceptions and error log entries,
    :attr:`requests` every URL the page asked for.
    """

    def __init__(self, binary: str, width: int = WIDTH, height: int = HEIGHT) -> None:
        self.width, self.height = width, height
        self.profile = tempfile.mkdtemp(prefix="p2s-chromium-")
        self.log = open(Path(self.profile) / "stderr.log", "wb")  # noqa: SIM115
        args = [
            binary, "--headless=new", "--remote-debugging-pipe",
            "--enable-unsafe-swiftshader", "--use-angle=swiftshader", "--enable-webgl",
            "--ignore-gpu-blocklist", "--no-first-run", "--no-default-browser-check",
            "--disable-extensions", "--disable-background-networking", "--disable-sync",
            "--disable-component-update", "--disable-default-apps", "--mute-audio",
            "--hide-scrollbars", "--force-device-scale-factor=1",
            f"--window-size={width},{height}", f"--user-data-dir={self.profile}",
        ]  # fmt: skip
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            args.append("--no-sandbox")
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        # (moved above fd 9 first, so that making them fds 3 and 4 overwrites neither)
        to_browser_r, from_browser_w = (_high_fd(fd) for fd in (to_browser_r, from_browser_w))
        # the browser reads commands on fd 3 and writes replies on fd 4
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _EXEC_WITH_FDS, str(to_browser_r), str(from_browser_w),
             *args, "about:blank"],
            pass_fds=(to_browser_r, from_browser_w),
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self.log,
        )  # fmt: skip
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._next_id = 0
        self._replies: dict[int, dict] = {}
        self._events: list[dict] = []
        self._cond = threading.Condition()
        self._closed = False
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self.session: str | None = None
        self.errors: list[str] = []
        self.requests: list[str] = []

    # -- protocol
    def _read(self) -> None:
        buf = b""
        while True:
            try:
                chunk = os.read(self._from_browser, 1 << 16)
            except OSError:
                chunk = b""
            if not chunk:
                with self._cond:
                    self._closed = True
                    self._cond.notify_all()
                return
            buf += chunk
            while b"\0" in buf:
                raw, buf = buf.split(b"\0", 1)
                msg = json.loads(raw)
                with self._cond:
                    if "id" in msg:
                        self._replies[msg["id"]] = msg
                    else:
                        self._events.append(msg)
                        self._note(msg)
                    self._cond.notify_all()

    def _note(self, msg: dict) -> None:
        """Keep what a test checks: errors of the page and the URLs it requested."""
        method, p = msg.get("method"), msg.get("params", {})
        if method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            args = p.get("args", [])
            self.errors.append(
                "console: " + " ".join(str(a.get("value", a.get("description", ""))) for a in args)
            )
        elif method == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            text = d.get("exception", {}).get("description") or d.get("text", "")
            self.errors.append(f"exception: {text}")
        elif method == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            self.errors.append(f"log: {p['entry'].get('text', '')} {p['entry'].get('url', '')}")
        elif method == "Network.requestWillBeSent":
            self.requests.append(p.get("request", {}).get("url", ""))

    def send(self, method: str, params: dict | None = None, timeout: float = 60.0) -> dict:
        """Send one command (to the page's session once attached); its result."""
        with self._cond:
            self._next_id += 1
            msg_id = self._next_id
        msg = {"id": msg_id, "method": method, "params": params or {}}
        if self.session is not None and not method.startswith(("Target.", "Browser.")):
            msg["sessionId"] = self.session
        os.write(self._to_browser, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        with self._cond:
            while msg_id not in self._replies:
                left = deadline - time.monotonic()
                if self._closed or left <= 0:
                    raise CdpError(f"{method}: no reply ({self._stderr_tail()})")
                self._cond.wait(left)
            reply = self._replies.pop(msg_id)
        if "error" in reply:
            raise CdpError(f"{method}: {reply['error']}")
        return reply.get("result", {})

    def wait_event(self, method: str, timeout: float = 60.0) -> dict:
        deadline = time.monotonic() + timeout
        with self._cond:
            while True:
                for i, ev in enumerate(self._events):
                    if ev.get("method") == method:
                        return self._events.pop(i).get("params", {})
                left = deadline - time.monotonic()
                if self._closed or left <= 0:
                    raise CdpError(f"no {method} event ({self._stderr_tail()})")
                self._cond.wait(left)

    def _stderr_tail(self) -> str:
        self.log.flush()
        text = (Path(self.profile) / "stderr.log").read_text(errors="replace")
        return "browser stderr: " + text[-600:].replace("\n", " | ")

    # -- page
    def open(self, path: str | Path, ready: str = "window.viewerReady === true",
             timeout: float = 60.0) -> None:  # fmt: skip
        """Load ``path`` in a fresh tab of ``width`` x ``height`` and wait until the
        expression ``ready`` is true (or ``window.viewerError`` is set: the test sees it)."""
        if self.session is None:
            target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
            self.session = self.send(
                "Target.attachToTarget", {"targetId": target, "flatten": True}
            )["sessionId"]
            for domain in ("Page", "Runtime", "Log", "Network"):
                self.send(f"{domain}.enable")
            self.send(
                "Emulation.setDeviceMetricsOverride",
                {"width": self.width, "height": self.height, "deviceScaleFactor": 1,
                 "mobile": False},
            )  # fmt: skip
        with self._cond:
            self._events.clear()
        self.send("Page.navigate", {"url": Path(path).resolve().as_uri()})
        self.wait_event("Page.loadEventFired", timeout)
        deadline = time.monotonic() + timeout
        while not self.evaluate(f"Boolean(({ready}) || window.viewerError)"):
            if time.monotonic() > deadline:
                raise CdpError(f"page not ready after {timeout} s: {ready}")
            time.sleep(0.05)

    def evaluate(self, expression: str):
        """The value of a JavaScript expression in the page (JSON-able values)."""
        result = self.send(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
        )
        if "exceptionDetails" in result:
            raise CdpError(f"{expression}: {result['exceptionDetails'].get('text')}")
        return result.get("result", {}).get("value")

    def settle(self) -> None:
        """Wait for two animation frames (what was asked to be drawn is on screen)."""
        self.evaluate(
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(1))))"
        )

    def screenshot(self) -> bytes:
        """PNG of the page's viewport."""
        self.settle()
        data = self.send("Page.captureScreenshot", {"format": "png"})["data"]
        return base64.b64decode(data)

    def close(self) -> None:
        try:
            if self.proc.poll() is None:
                try:
                    self.send("Browser.close", timeout=10)
                except (CdpError, OSError):
                    pass
                try:
                    self.proc.wait(10)
                except subprocess.TimeoutExpired:
                    self.proc.kill()
                    self.proc.wait(10)
        finally:
            for fd in (self._to_browser, self._from_browser):
                try:
                    os.close(fd)
                except OSError:
                    pass
            self.log.close()
            shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self) -> Chromium:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def write_pages(scenes: Path) -> list[Path]:
    """scene.html of every scene folder in ``scenes`` (embedding the scene.glb written
    there) and ``scenes/index.html``; the scene folders, sorted."""
    from pair2scene.io.atomic import atomic_write_bytes
    from pair2scene.io.scene_json import read_scene
    from pair2scene.io.viewer import SCENE_HTML, page_html, scene_info, write_index

    folders = sorted(p.parent for p in scenes.glob("*/scene.json") if not p.parent.name[0] == ".")
    for folder in folders:
        info = scene_info(read_scene(folder / "scene.json"))
        page = page_html((folder / "scene.glb").read_bytes(), info, "../index.html")
        atomic_write_bytes(folder / SCENE_HTML, page)
    write_index(scenes)
    return folders


def generate(scenes: Path) -> None:
    for room, num, seed in ROOMS:
        subprocess.run(
            [sys.executable, "-m", "pair2scene", "generate", "--room", room, "--num", str(num),
             "--seed", str(seed), "--out", str(scenes / room)],
            check=True, stdout=subprocess.DEVNULL,
        )  # fmt: skip
        for folder in (scenes / room).iterdir():  # one flat folder of scene folders
            if folder.is_dir() and not folder.name.startswith("."):
                folder.rename(scenes / folder.name)
        shutil.rmtree(scenes / room)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", type=Path, help="scene folder to make (default: temporary)")
    ap.add_argument("--docs", type=Path, default=Path(__file__).resolve().parents[1] / "docs")
    args = ap.parse_args(argv)
    binary = find_chromium()
    if binary is None:
        print("no chromium on PATH (apt-get install -y chromium)", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as tmp:
        scenes = args.scenes or Path(tmp) / "scenes"
        scenes.mkdir(parents=True, exist_ok=True)
        if not any(scenes.glob("*/scene.json")):
            generate(scenes)
        folders = write_pages(scenes)
        glb = (folders[0] / "scene.glb").read_bytes()
        if b'"name":"pair2scene"' not in glb:
            print("warning: scene.glb has no pair2scene root node (the old z-up writer?)")
        with Chromium(binary) as browser:
            browser.open(folders[0] / "scene.html")
            room_png = browser.screenshot()
            browser.open(scenes / "index.html", ready=GALLERY_READY)
            gallery_png = browser.screenshot()
            if browser.errors:
                print("page errors:", *browser.errors, sep="\n  ")
                return 1
        args.docs.mkdir(parents=True, exist_ok=True)
        (args.docs / "viewer_room.png").write_bytes(room_png)
        (args.docs / "viewer_gallery.png").write_bytes(gallery_png)
    print(f"wrote {args.docs / 'viewer_room.png'} ({folders[0].name}), "
          f"{args.docs / 'viewer_gallery.png'} ({len(folders)} scenes)")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
