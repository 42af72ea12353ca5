"""Runs bounce's notebook view (``widget.js``) in headless Chromium: writes a View's frames
where ``harness.html`` reads them, serves the folder on 127.0.0.1 and drives the page with
``web/widget-e2e.mjs`` (playwright-core, installed in web/ by scripts/test). Used by
``test_widget.py`` and by ``bench.py`` (the frame rate in BENCHMARKS.md)."""

import contextlib
import functools
import http.server
import json
import pathlib
import shutil
import subprocess
import threading

import bounce.widget

ROOT = pathlib.Path(__file__).resolve().parents[4]
HERE = pathlib.Path(__file__).resolve().parent


def save_frame(view, folder, k):
    """Writes the view's synced state as frame ``k``: the JSON traits and one .bin a buffer."""
    data = pathlib.Path(folder) / "data"
    data.mkdir(parents=True, exist_ok=True)
    state = {
        name: getattr(view, name)
        for name in ("bounds", "obstacles", "frame", "width", "histogram", "renderer", "playing")
    }
    (data / f"frame{k}.json").write_text(json.dumps(state))
    for name in ("positions", "radii", "shades"):
        (data / f"frame{k}.{name}.bin").write_bytes(getattr(view, name))


def prepare(folder):
    """Copies the installed package's widget.js (what a notebook loads) and the harness page."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    shutil.copy(pathlib.Path(bounce.widget.__file__).with_name("widget.js"), folder / "widget.js")
    shutil.copy(HERE / "harness.html", folder / "harness.html")


@contextlib.contextmanager
def serve(folder):
    """A static server for ``folder`` on a free port; yields its URL."""
    handler = functools.partial(_Quiet, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def node(script, *args, timeout=240):
    """Runs ``web/SCRIPT`` under node (playwright-core in web/node_modules, Debian's
    Chromium) and returns the JSON report its last line prints."""
    if not (ROOT / "web" / "node_modules" / "playwright-core").exists():
        raise RuntimeError("web/node_modules lacks playwright-core: scripts/test installs it")
    if shutil.which("node") is None or not pathlib.Path("/usr/bin/chromium").exists():
        raise RuntimeError("node and /usr/bin/chromium are needed: scripts/test installs them")
    done = subprocess.run(
        ["node", str(ROOT / "web" / script), *map(str, args)],
        cwd=ROOT / "web",
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def drive(url, screenshot, mode, renderer="auto"):
    """Runs web/widget-e2e.mjs (the harness page) and returns its report."""
    return node("widget-e2e.mjs", url, screenshot, mode, renderer)


@contextlib.contextmanager
def jupyterlab(folder):
    """A JupyterLab server for ``folder`` on a free port (no token, the app exposed to the
    page for the driver); yields its URL."""
    import socket
    import sys
    import time
    import urllib.request

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen(
        [
            sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root",
            f"--port={port}", "--ServerApp.ip=127.0.0.1", "--IdentityProvider.token=",
            "--ServerApp.password=", "--LabApp.expose_app_in_browser=True",
            f"--ServerApp.root_dir={folder}",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 90
        while True:
            try:
                urllib.request.urlopen(f"{url}/api/status", timeout=2)
                break
            except OSError:
                if time.monotonic() > deadline or server.poll() is not None:
                    raise RuntimeError("JupyterLab did not start")
                time.sleep(0.5)
        yield url
    finally:
        server.terminate()
        try:
            server.wait(timeout=20)
        except subprocess.TimeoutExpired:
            server.kill()


def drive_jupyterlab(url, notebook, screenshot, seconds=5):
    """Runs web/jupyter-e2e.mjs on ``notebook`` (a path under the server's folder)."""
    return node("jupyter-e2e.mjs", url, notebook, screenshot, seconds, timeout=400)


def notebook(path, setup):
    """Writes a notebook whose first cell runs ``setup`` (making ``view``) and shows ``view``."""
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(setup), nbformat.v4.new_code_cell("view")]
    nb.metadata["kernelspec"] = {"display_name": "Python 3", "language": "python", "name": "python3"}
    nbformat.write(nb, str(path))
