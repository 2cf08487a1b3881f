"""Pages of the report for further studies (config further_studies), each
run on its own by its own workflow config: its committed statistics and
equations as one HTML page, with a caption that states its numbers."""
import sys
from pathlib import Path

sm = snakemake  # noqa: F821
sys.stderr = sys.stdout = open(sm.log[0], "w")

import pandas as pd  # noqa: E402

from masonrydem.report import captions, tables  # noqa: E402

for name, study in sm.params.studies.items():
    st = pd.read_csv(sm.input[f"{name}_statistics"])
    eq = pd.read_csv(sm.input[f"{name}_equations"])
    page = tables.html_page([("P_max and strength per variant, level and mode", st), ("Prediction equations", eq)],
                            study["title"])
    Path(sm.output[f"{name}_page"]).write_text(page)
    spec = sm.params.specs[name]
    ns = st[(st.variant == spec["variant"]) & (st["mode"] == "all")]
    means = "; ".join(f"{getattr(r, spec['level_column']):g} {spec['level_unit']}: {r.P_max_mean_kN:.2f} kN "
                      f"(COV {r.P_max_cov:.2f}), {r.strength_mean_mpa:.2f} MPa, brick share {r.brick_share:.0%}"
                      for r in ns.itertuples())
    eqs = eq.set_index("mode").equation
    captions.write_caption(sm.input.template, sm.output[f"{name}_caption"], title=study["title"],
                           results=study["results"], workflow=study["workflow"], means=means,
                           joint=eqs.get("joint", "none"), brick=eqs.get("brick", "none"), variant=spec["variant"])
    print(name, st.shape, eq.shape)
