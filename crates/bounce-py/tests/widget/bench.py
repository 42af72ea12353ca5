"""The notebook view's frame rate at 10^5 discs (BENCHMARKS.md): the page alone in headless
Chromium (harness.html, frames answered at once), Python's cost a frame (a step and a push),
and the whole loop in a real JupyterLab (kernel, comm, websocket, page).

    target/venv/bin/python crates/bounce-py/tests/widget/bench.py
"""

import pathlib
import platform
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

import harness  # noqa: E402
from test_widget import hundred_thousand  # noqa: E402

from bounce.widget import View  # noqa: E402


def cpu():
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor()


def main():
    print(f"machine: {cpu()}, {len(pathlib.Path('/proc/cpuinfo').read_text().split('processor')) - 1} cores")
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        world = hundred_thousand()
        view = View(world, every=1, max_fps=None)
        harness.prepare(folder / "page")
        for k in range(8):
            if k:
                view.step()
            harness.save_frame(view, folder / "page", k)
        times = []
        for _ in range(30):
            t = time.perf_counter()
            view.step()
            times.append(time.perf_counter() - t)
        times.sort()
        print(f"python, a step and a push: mean {1e3 * sum(times) / len(times):.1f} ms, "
              f"median {1e3 * times[len(times) // 2]:.1f} ms")
        with harness.serve(folder / "page") as url:
            for renderer in ("raster", "webgl"):
                r = harness.drive(url, folder / "page.png", "fps", renderer)
                print(f"page alone ({r['renderer']}): {r['fps']:.1f} frames/s, "
                      f"median draw {r['draw_ms_median']:.1f} ms (JavaScript's side)")
        harness.notebook(
            folder / "big.ipynb",
            f"import sys\nsys.path.insert(0, {str(HERE.parent)!r})\n"
            "from test_widget import hundred_thousand\nfrom bounce.widget import View\n"
            "world = hundred_thousand()\nview = View(world, every=1)",
        )
        with harness.jupyterlab(folder) as url:
            r = harness.drive_jupyterlab(url, "big.ipynb", folder / "lab.png", seconds=8)
        assert "error" not in r, r
        print(f"JupyterLab, playing: {r['frames_per_second']:.1f} frames/s from the kernel, "
              f"{r['draws_per_second']:.1f} drawn/s ({r['renderer']})")


if __name__ == "__main__":
    main()
