"""Where the strips' loads really act: the x of each bearing strip's
resultant (the centroid of its sub-contacts' normal forces) against the
strip's centre line, at the peak of the load, and the moment arm that
follows, for strips of several widths (docs/findings.md, "What each
modelling choice does").

    .venv/bin/python benchmarks/strip_resultants.py [--widths 0.01 0.02 0.04] [--set KEY=VALUE ...]
        [--out results/modelform/strip_resultants.csv]

A strip is one node that translates without turning, bearing on the wall
through compression-only sub-contacts (contacts.Strip): as the wall turns
over it, its pressure gathers toward one edge.  The strength formula
takes the nominal arm a (support to load, 275 mm); the arm of the
resultants is a - the shifts.  Runs each width with strips that only
translate (``loading.bending.strips_turn=false``) and with strips that
turn; prints, per run, P_max, each strip's shift toward the span's centre
or its ends, and the effective arm; and writes ``--out``: per run the
strips, the width, P_max, the mean arm of the resultants, P_max times it,
the largest shift and the settings (docs/findings.md's table is this file,
tests/test_docs_numbers.py).
"""
import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from masonrydem.specimen.protocol import CHUNK, precompress
from masonrydem.scene import build_scene
from masonrydem.dem import Controls, init, prescribe
from masonrydem.specimen.build import build
from masonrydem.dem.stops import Stops, run


def bearing_x(state, strip):
    """x of the resultant of ``strip``'s normal forces: the centroid of the
    sub-contacts' force magnitudes along the strip's normal."""
    b, a = state.bearings, state.assembly
    s = strip.sc
    xyz = np.einsum("sk,skd->sd", b.w[s, :4], (a.nodes.x0 + state.nodes.u)[b.nodes[s, :4]])
    fn = np.abs(np.einsum("sd,sd->s", b.force[s], b.axes[s, :3]))
    return float(np.sum(fn * xyz[:, 0]) / np.sum(fn))


def at_peak(scene):
    """Runs the bending test (after the precompression, if any) and returns
    P_max (kN), the peak the protocol counts, and the x of every strip's
    resultant at the end of the chunk nearest it."""
    specimen = build(scene)
    state = init(specimen.assembly, specimen.numerics)
    u0 = 0.0
    if scene.loading.precompression.pressure > 0:
        state, pre = precompress(state, specimen)
        u0 = float(pre.record.last.disp_of("load")[0])
    drive = scene.loading.drive
    state = prescribe(state, specimen.drive, specimen.velocity)
    seen = []

    def watch(st, history):
        seen.append((st.step, [bearing_x(st, s) for s in st.assembly.strips]))
    stops = Stops(disp_limit=u0 + drive.max_displacement, load_drop=drive.load_drop, monitor="load", balance="support")
    state, record, _ = run(state, drive.max_steps, stops, Controls(ramp_steps=drive.ramp_steps), chunk=CHUNK,
                           record_every=scene.discretization.record_every, progress=watch)
    peak = record.peaks[record.history.group("load")]      # the peak the protocol counts (near equilibrium)
    step, xs = min(seen, key=lambda r: abs(r[0] - peak.step))
    return peak.load / 1e3, xs, state.assembly.strips


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="config/scenes/willis.yaml")
    ap.add_argument("--widths", nargs="*", type=float, default=[0.010, 0.020, 0.040])
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--out", type=Path, default=Path("results/modelform/strip_resultants.csv"))
    args = ap.parse_args()
    rows = []
    for turn in (False, True):
        for w in args.widths:
            scene = build_scene(args.scene, args.set + [f"loading.bending.strip_width={w}",
                                                        f"loading.bending.strips_turn={str(turn).lower()}"])
            P, xs, strips = at_peak(scene)
            bend = scene.loading.bending
            centre = 0.5 * (min(bend.supports) + max(bend.supports))
            shifts = {s.name: (x - s.x0[0]) * np.sign(centre - s.x0[0]) * 1e3 for s, x in zip(strips, xs)}
            supports, loads = (sorted(x for s, x in zip(strips, xs) if s.name.startswith(kind))
                               for kind in ("support", "load"))
            arm = 1e3 * np.mean([abs(xl - xsup) for xsup, xl in zip(supports, loads)])
            print(f"strips {'turn' if turn else 'translate'}, width {w * 1e3:4.0f} mm: P_max {P:7.3f} kN; shift "
                  "toward the centre (mm): " + ", ".join(f"{k} {v:+.1f}" for k, v in shifts.items())
                  + f"; arm of the resultants {arm:.1f} mm (nominal "
                  f"{1e3 * (min(bend.loads) - min(bend.supports)):.0f})", flush=True)
            rows.append(dict(strips="turn" if turn else "translate", width_mm=round(w * 1e3, 3), P_max_kN=P,
                             arm_mm=arm, moment_kN_mm=P * arm, max_shift_mm=max(abs(v) for v in shifts.values()),
                             settings=" ".join(args.set)))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame(rows).to_csv(args.out, index=False, float_format="%.6g")


if __name__ == "__main__":
    main()
