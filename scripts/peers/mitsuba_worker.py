"""mitsuba_worker.py — renders for time_to_error.py with Mitsuba 3, one process per variant.

Run by time_to_error.py as `PYTHON mitsuba_worker.py VARIANT THREADS` with a Python that
imports mitsuba. Reads one JSON command a line on stdin, answers each with one line
"@@PEER@@ {json}" on stdout (anything else on stdout is Mitsuba's own output):
  {"cmd": "load", "xml": PATH}                   -> {"ok": true}
  {"cmd": "render", "spp": N, "seed": S, "out": PATH.npy}
        -> {"ok": true, "render_s": seconds}   (the time around mi.render and the read-back
           of the image, which for the LLVM variant is where the kernel runs)
  {"cmd": "quit"}
Errors answer {"ok": false, "error": "..."}.
"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from worker_protocol import reply, serve  # noqa: E402


def main():
    variant, threads = sys.argv[1], int(sys.argv[2])
    try:
        import drjit as dr
        import mitsuba as mi
        import numpy as np
        mi.set_variant(variant)
        if threads > 0:
            dr.set_thread_count(threads)
        mi.set_log_level(mi.LogLevel.Warn)
    except Exception as e:  # noqa: BLE001 — reported to the driver, which skips this peer
        reply({"ok": False, "error": f"{type(e).__name__}: {e}"})
        return
    reply({"ok": True, "variant": variant, "mitsuba": mi.__version__, "threads": threads})
    scene = None

    def load(cmd):
        nonlocal scene
        scene = mi.load_file(cmd["xml"])
        return {"ok": True}

    def render(cmd):
        t = time.perf_counter()
        img = mi.render(scene, spp=int(cmd["spp"]), seed=int(cmd["seed"]))
        px = np.array(img, dtype=np.float32)
        render_s = time.perf_counter() - t
        np.save(cmd["out"], px[..., :3])
        return {"ok": True, "render_s": render_s}

    serve({"load": load, "render": render})


if __name__ == "__main__":
    main()
