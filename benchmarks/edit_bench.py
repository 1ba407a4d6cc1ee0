"""``make bench``: ``dgpc edit`` latency, by the replay's code path (the page's solver thread)
with the page's server running (no browser): the demo wall's handle pattern at 21×13 and
41×41, three handles placed and the fourth held where it starts (the net settled, as the page
opens), then the fourth dragged to its target in 40 moves 40 ms apart and released.

Prints, per size and per way of running a drag event, the median and largest latency from a
drag event's arrival to its net's data sent to the page (server side; events a newer one
superseded before they ran are counted apart), the solver thread's CPU time per event shown
(its cost on an idle core: the machine's load does not inflate it), the numeric
factorizations per event shown,
and the seconds from the release to the settled net (``optimize``'s run). The ways:
``factorize`` one guided-projection iteration per event (a new factorization each: what a
drag event cost before predictor steps), ``predictor`` the page's way (an iteration every
``REFACTOR`` events, predictor steps between). Targets: ≤ 50 ms at 21×13, ≤ 200 ms at 41×41.

Then the fabrication figures (:func:`fabrication`): per drag event of 20, the live estimate
(the last strips bent onto the moved net), against the pipeline's run on release; targets
≤ 100 ms at 21×13 and ≤ 1 s at 41×41 per event.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "samples"))
import generate  # noqa: E402

from dgpc_cli.edit import session as edit_session  # noqa: E402
from dgpc_cli.edit.page import EditPage  # noqa: E402
from dgpc_cli.edit.replay import replay  # noqa: E402
from dgpc_cli.fitting.modes import mode_weights  # noqa: E402
from dgpc_cli.io.drags import read_drags  # noqa: E402
from dgpc_cli.io.handles import read_handles  # noqa: E402
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize  # noqa: E402

SIZES = {(21, 13): 0.050, (41, 41): 0.200}
MOVES, PERIOD = 40, 0.04


def _drags(d: Path, m: int, n: int) -> tuple[Path, Path]:
    source, span, drag = generate.HANDLE_SETS["wall"]
    profile = generate.read_profile_csv(ROOT / "samples" / "profiles" / source)
    handles = json.loads(generate.handles_json(profile, m, n, span, drag))["handles"]
    net = d / "wall"
    subprocess.run([sys.executable, "-m", "dgpc_cli.cli.main", "-q", "init", "--surface",
                    "revolution", "--profile", str(ROOT / "samples/profiles/wall.csv"), "--rows",
                    str(m), "--cols", str(n), "--span", str(span), "--units", "m", "-o",
                    str(net)], check=True, capture_output=True)
    f = np.array([[float(c) for c in line.split()[1:]]
                  for line in (d / "wall.obj").read_text().splitlines()
                  if line.startswith("v ")]).reshape(m, n, 3)
    last = handles[3]
    start = f[tuple(last["index"])]
    held = d / "handles.json"          # three handles placed, the fourth where it starts
    held.write_text(json.dumps({"handles": [*handles[:3], {"index": last["index"],
                                                           "offset": [0.0, 0.0, 0.0]}]}))
    events = []
    for k in range(1, MOVES + 1):
        target = start + (np.array(last["target"]) - start) * k / MOVES
        events.append({"handle": last["index"], "target": target.tolist(),
                       "time": PERIOD * k, **({"end": True} if k == MOVES else {})})
    path = d / "drags.json"
    path.write_text(json.dumps({"events": events}))
    (d / "goal.json").write_text(json.dumps(last["target"]))
    return net, held, path


class _NoGestures:
    """The page's gestures go nowhere: the drags come from the replay."""

    def __getattr__(self, name):
        return lambda *args: None


def run(d: Path, net: Path, held: Path, drags: Path, refactor: int) -> dict:
    """One replay of ``drags`` on a fresh session with a page; its log."""
    settings = OptimizeSettings("isometric", mode_weights("isometric"), steps=5)
    prepared = prepare_optimize(net, settings)
    ids, targets = read_handles(held, prepared.net.shape, prepared.net.f_mm, scale=prepared.mm)
    session = edit_session.EditSession(prepared, {int(i): tuple(float(c) for c in t / prepared.mm)
                                                  for i, t in zip(ids, targets, strict=True)})
    page = EditPage(session.frame(), _NoGestures(), host="127.0.0.1", port=0, title="bench",
                    max_strain=settings.max_strain)
    saved = edit_session.REFACTOR
    edit_session.REFACTOR = refactor
    try:
        _, log = replay(session, read_drags(drags, prepared.net.shape), d / f"out{refactor}",
                        show=page.show)
    finally:
        edit_session.REFACTOR = saved
        page.stop()
    return log


#: The live fabrication figures: drag events timed per size, and their targets (seconds).
FAB_DRAGS = 20
FAB_TARGETS = {(21, 13): 0.100, (41, 41): 1.0}


def fabrication(net: Path, held: Path, m: int, n: int) -> None:
    """The fabrication figures while the fourth handle is dragged in ``FAB_DRAGS`` events
    (the live estimate: the last strips bent onto the moved net) against the pipeline's run
    (``planarize-strips`` + ``unfold``, their defaults) on the settled net; one line per
    size: the medians and largest per event (wall and CPU), the strips bent per event, the
    pipeline's seconds and the ratio, and the template counts shown live and on release."""
    settings = OptimizeSettings("isometric", mode_weights("isometric"), steps=5)
    prepared = prepare_optimize(net, settings)
    ids, targets = read_handles(held, prepared.net.shape, prepared.net.f_mm, scale=prepared.mm)
    session = edit_session.EditSession(prepared, {int(i): tuple(float(c) for c in t / prepared.mm)
                                                  for i, t in zip(ids, targets, strict=True)})
    session.settle()
    t0, c0 = time.perf_counter(), time.process_time()
    opened = session.fabrication()["strips"]
    first = (time.perf_counter() - t0, time.process_time() - c0)
    handles = json.loads(held.read_text())["handles"]
    u, v = handles[3]["index"]
    start = np.array(session.position(u, v))
    goal = np.array(json.loads((net.parent / "goal.json").read_text()))
    walls, cpus, live = [], [], None
    for k in range(1, FAB_DRAGS + 1):
        session.drag(u, v, start + (goal - start) * k / FAB_DRAGS)
        t0, c0 = time.perf_counter(), time.process_time()
        live = session.fabrication()["strips"]
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    session.settle()
    t0, c0 = time.perf_counter(), time.process_time()
    released = session.fabrication()["strips"]
    release = (time.perf_counter() - t0, time.process_time() - c0)
    target = FAB_TARGETS[(m, n)]
    print(f"{m:>3}×{n:<3}  live per event: median {1000 * statistics.median(walls):.0f} ms "
          f"(CPU {1000 * statistics.median(cpus):.0f} ms), largest {1000 * max(walls):.0f} "
          f"ms, target {1000 * target:.0f} ms; pipeline on opening {first[0]:.2f} s (CPU "
          f"{first[1]:.2f} s), on release {release[0]:.2f} s (CPU {release[1]:.2f} s): live / "
          f"pipeline {statistics.median(cpus) / release[1]:.3f} (CPU); templates: opening "
          f"{opened.get('templates')}, live {live.get('templates')}, released "
          f"{released.get('templates')} ({released.get('method')})")


def main() -> None:
    load = os.getloadavg()[0]
    print(f"dgpc edit: latency of a drag, event to the net's data sent to the page (server "
          f"side); load average {load:.2f} on {os.cpu_count()} cores")
    print(f"{'net':>7}  {'events':>15}  {'shown':>5}  {'factorizations':>20}  {'median ms':>9}  "
          f"{'max ms':>7}  {'cpu ms':>7}  {'target ms':>9}  {'release→settled s':>17}  state")
    for (m, n), target in SIZES.items():
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            net, held, drags = _drags(d, m, n)
            medians, cpus = {}, {}
            for way, refactor in (("factorize", 1), ("predictor", edit_session.REFACTOR)):
                log = run(d, net, held, drags, refactor)
                drag = [e for e in log["events"] if e["action"] == "drag"]
                shown = [e for e in drag if "shown" in e]
                ms = [1000 * e["shown"] for e in shown]
                medians[way] = statistics.median(ms)
                cpu = statistics.median(1000 * e["cpu"] for e in shown)
                cpus[way] = cpu
                settle = log["settles"][-1] if log["settles"] else {"seconds": float("nan"),
                                                                    "state": "-"}
                print(f"{m:>3}×{n:<3}  {len(drag):>3} {way:>11}  {len(shown):>5}  "
                      f"{''.join(str(e['factorizations']) for e in shown):>20}  "
                      f"{medians[way]:>9.1f}  {max(ms):>7.1f}  {cpu:>7.1f}  {1000 * target:>9.0f}  "
                      f"{settle['seconds']:>17.2f}  {settle['state']}")
            print(f"{m:>3}×{n:<3}  predictor / factorize: median latency "
                  f"{medians['predictor'] / medians['factorize']:.2f}, median CPU "
                  f"{cpus['predictor'] / cpus['factorize']:.2f}")
            fabrication(net, held, m, n)
    print(f"load average {os.getloadavg()[0]:.2f} at the end; cpu ms: the solver thread's own "
          "CPU time per event shown (median), what it costs on an idle core")


if __name__ == "__main__":
    main()
