"""``make bench``: ``dgpc edit`` latency, through ``--replay`` (the page's solver thread
without a page): the demo wall's handle pattern at 21×13 and 41×41, three handles placed and
the fourth held where it starts (the net settled, as the page opens), then the fourth dragged to
its target in 20 moves 40 ms apart and released.

Prints, per size, the median and largest latency from a drag event to the updated net and its
figures (server side; events a newer one superseded before they ran are counted apart), and
the seconds from the release to the settled net (``optimize``'s run). Targets: ≤ 50 ms at
21×13, ≤ 200 ms at 41×41.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "samples"))
import generate  # noqa: E402

SIZES = {(21, 13): 0.050, (41, 41): 0.200}
MOVES, PERIOD = 20, 0.04


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
    return net, held, path


def main() -> None:
    print("dgpc edit --replay: latency of a drag (server side)")
    print(f"{'net':>7}  {'events':>6}  {'shown':>5}  {'median ms':>9}  {'max ms':>7}  "
          f"{'target ms':>9}  {'release→settled s':>17}  state")
    for (m, n), target in SIZES.items():
        with tempfile.TemporaryDirectory() as tmp:
            d = Path(tmp)
            net, held, drags = _drags(d, m, n)
            subprocess.run([sys.executable, "-m", "dgpc_cli.cli.main", "-q", "edit", str(net),
                            "--handles", str(held), "--replay", str(drags), "--steps", "5",
                            "-o", str(d / "out")], capture_output=True)
            log = json.loads((d / "out-replay.json").read_text())
            drag = [e for e in log["events"] if e["action"] == "drag"]
            shown = [e["latency"] for e in drag if "latency" in e]
            settle = log["settles"][-1] if log["settles"] else {"seconds": float("nan"),
                                                                "state": "-"}
            print(f"{m:>3}×{n:<3}  {len(drag):>6}  {len(shown):>5}  "
                  f"{1000 * statistics.median(shown):>9.1f}  {1000 * max(shown):>7.1f}  "
                  f"{1000 * target:>9.0f}  {settle['seconds']:>17.2f}  {settle['state']}")


if __name__ == "__main__":
    main()
