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
import json
import sys
import time
import traceback

MARK = "@@PEER@@ "


def reply(obj):
    sys.stdout.write(MARK + json.dumps(obj) + "\n")
    sys.stdout.flush()


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
    for line in sys.stdin:
        if not line.strip():
            continue
        cmd = json.loads(line)
        try:
            if cmd["cmd"] == "quit":
                reply({"ok": True})
                return
            if cmd["cmd"] == "load":
                scene = mi.load_file(cmd["xml"])
                reply({"ok": True})
            elif cmd["cmd"] == "render":
                t = time.perf_counter()
                img = mi.render(scene, spp=int(cmd["spp"]), seed=int(cmd["seed"]))
                px = np.array(img, dtype=np.float32)
                render_s = time.perf_counter() - t
                np.save(cmd["out"], px[..., :3])
                reply({"ok": True, "render_s": render_s})
            else:
                reply({"ok": False, "error": f"unknown command {cmd['cmd']!r}"})
        except Exception as e:  # noqa: BLE001
            reply({"ok": False, "error": f"{type(e).__name__}: {e}",
                   "trace": traceback.format_exc()})


if __name__ == "__main__":
    main()
