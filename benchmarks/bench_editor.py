"""``shapegen edit``: seconds from a slider change (``POST /api/attrs``) to the verdict.

The editor's server runs in this process on a free port; a client posts attr changes one after
the other, as the page does during a drag (it sends the next change when the last answer is in),
and times each request until the answer with the new verdict has been read. Printed per model:
the median, the smallest and the largest of the timed changes, the server's own update time
(build + judge), the median CPU seconds of this process per change (the better estimate on a
shared machine), how many of the designs stand, and the load average. Two cases:

- ``drag``: changes back to back, the stable-range scan never starts (it waits for a pause);
- ``pauses``: a pause of ``--pause`` s after each change, so the background scan of the free
  attrs is running when the next change arrives (it stops after its current evaluation).

Targets (issue): under 0.2 s on barrel_vault.grammar (140 blocks), under 2 s on cluny.grammar
(1 072 blocks).

    .venv/bin/python benchmarks/bench_editor.py
    .venv/bin/python benchmarks/bench_editor.py --models barrel_vault --repeat 20
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import statistics
import threading
import time

from shapegen.editor import EditorSession, make_server

# model -> (rule file, the starting design, the attr dragged, the values it is dragged through)
CASES = {
    # the flyers at 60 degrees, where the vault stands (the file's 85 degrees need tension)
    "barrel_vault": ("barrel_vault.grammar", {"angle": 60.0}, "span",
                     [5.8, 6.0, 5.9, 6.1, 5.7, 6.0, 5.85, 6.05, 5.95, 6.0]),
    # as in its file: it needs tension, so each change costs two solves
    "cluny": ("cluny.grammar", {}, "nave_span", [10.6, 10.8, 10.7, 10.9, 10.8, 10.65]),
    # after Optimize (the four @Free attrs found by the search): it stands, one solve
    "cluny_standing": (
        "cluny.grammar",
        {"wall_thickness": 2.5, "buttress_thickness": 2.7265, "window_width": 1.9652,
         "column_size": 1.1713},
        "nave_span",
        [10.6, 10.8, 10.7, 10.9, 10.8, 10.65],
    ),
}  # fmt: skip


def post(port: int, path: str, body: dict) -> dict:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    try:
        connection.request("POST", path, json.dumps(body), {"Content-Type": "application/json"})
        response = connection.getresponse()
        content = json.loads(response.read())
        if response.status != 200:
            raise RuntimeError(content["error"])
        return content
    finally:
        connection.close()


def run(model: str, repeat: int, pause: float | None) -> None:
    grammar, start, name, values = CASES[model]
    values = (values * (repeat // len(values) + 1))[:repeat]
    session = EditorSession(grammar, attrs=start, scan=pause is not None)
    server = make_server(session, 0)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    port = server.server_address[1]
    seconds, cpu, updates, stands = [], [], [], []
    try:
        for value in values:
            started, started_cpu = time.perf_counter(), time.process_time()
            state = post(port, "/api/attrs", {name: value})
            seconds.append(time.perf_counter() - started)
            cpu.append(time.process_time() - started_cpu)
            updates.append(state["timings"]["update_s"])
            stands.append(state["verdict"]["stands"])
            if pause:
                time.sleep(pause)
    finally:
        server.shutdown()
        server.server_close()
        session.close()
    case = "drag" if pause is None else f"pauses of {pause:g} s"
    # CPU seconds of this process per change (server and client); with a scan running they
    # include the scan's, so only the drag's are shown
    cpu_median = f"{statistics.median(cpu):.3f}" if pause is None else "-"
    print(
        f"{model:<15} {state['grammar']['blocks']:>5} {case:<16} {len(seconds):>3} "
        f"{statistics.median(seconds):>8.3f} {min(seconds):>7.3f} {max(seconds):>7.3f} "
        f"{statistics.median(updates):>7.3f} {cpu_median:>7} {sum(stands):>6}  "
        f"{os.getloadavg()[0]:>4.1f}"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", default=",".join(CASES), help="comma-separated")
    parser.add_argument("--repeat", type=int, default=10, help="changes per model and case")
    parser.add_argument("--pause", type=float, default=1.0, help="seconds between changes")
    args = parser.parse_args(argv)
    print("seconds from POST /api/attrs to the answer with the verdict (the page's wait)")
    print(
        f"{'model':<15} {'blocks':>5} {'case':<16} {'n':>3} {'median':>8} {'min':>7} {'max':>7} "
        f"{'server':>7} {'cpu':>7} {'stands':>6}  load"
    )
    for model in args.models.split(","):
        repeat = args.repeat if not model.startswith("cluny") else max(3, args.repeat // 2)
        run(model, repeat, None)
        run(model, repeat, args.pause)


if __name__ == "__main__":
    main()
