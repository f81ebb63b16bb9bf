"""worker_protocol.py — the line protocol between time_to_error.py and its peer workers.

A worker reads one JSON command a line on stdin and answers each with one line
"@@PEER@@ {json}" on stdout (anything else on stdout is the renderer's own output).
{"cmd": "quit"} ends it; an unknown command or an exception answers {"ok": false, "error"}.
"""
import json
import sys
import traceback

MARK = "@@PEER@@ "


def reply(obj):
    sys.stdout.write(MARK + json.dumps(obj) + "\n")
    sys.stdout.flush()


def serve(handlers):
    """Answers commands from stdin until "quit": handlers maps a command name to a function
    of the command (a dict) that returns the reply."""
    for line in sys.stdin:
        if not line.strip():
            continue
        cmd = json.loads(line)
        try:
            if cmd["cmd"] == "quit":
                reply({"ok": True})
                return
            handler = handlers.get(cmd["cmd"])
            if handler is None:
                reply({"ok": False, "error": f"unknown command {cmd['cmd']!r}"})
            else:
                reply(handler(cmd))
        except Exception as e:  # noqa: BLE001 — reported to the driver
            reply({"ok": False, "error": f"{type(e).__name__}: {e}",
                   "trace": traceback.format_exc()})
