"""The geometry study's held-out formats (analysis/brick_formats.py): each format's brick
read from its study, and a predictor scored on runs it generated itself."""
import numpy as np
import pandas as pd
import pytest

from masonrydem.analysis import brick_formats as F


@pytest.mark.parametrize("study,brick", [
    ("config/studies/formats/uk.yaml", dict(L=215.0, H=65.0, W=102.5, t=10.0)),
    ("config/studies/formats/df.yaml", dict(L=240.0, H=52.0, W=115.0, t=12.0)),
    ("config/studies/nf.yaml", dict(L=240.0, H=71.0, W=115.0, t=12.0)),        # its scene's own brick
    ("config/studies/willis.yaml", dict(L=230.0, H=65.0, W=114.0, t=10.0)),
])
def test_a_format_is_its_study_s_brick(study, brick):
    geometry, variant = F.format_of(study)
    assert geometry == pytest.approx(brick, rel=1e-12) and variant == "nonspatial"


PREDICTOR = {
    "modes": {"joint": {"intercept": 0.1, "coef": {"f_tj*(L + t)/(2*(H + t))": 4.0, "sigma_v": 1.5}},
              "brick": {"intercept": 0.2, "coef": {"f_tu": 0.5}}},
    "inputs": {"f_tj": {"column": "f_tj_mpa"}, "f_tu": {"column": "f_tu_mpa"}, "sigma_v": {"column": "sigma_v_mpa"},
               "L": {"column": "L_mm"}, "H": {"column": "H_mm"}, "t": {"column": "t_mm"}},
    "variant": "nonspatial",
}


def _runs(n, brick, seed, error=0.0):
    """Runs whose strength is the lower of PREDICTOR's equations on the
    brick, times (1 + error), the mode the lower one's."""
    rng = np.random.default_rng(seed)
    f_tj, f_tu, sv = rng.uniform(0.1, 0.6, n), rng.uniform(2.5, 5.0, n), rng.choice([0.0, 0.5], n)
    r = (brick["L"] + brick["t"]) / (2 * (brick["H"] + brick["t"]))
    joint, brick_eq = 0.1 + 4.0 * f_tj * r + 1.5 * sv, 0.2 + 0.5 * f_tu
    return pd.DataFrame(dict(variant="nonspatial", ok=True, f_tj_mpa=f_tj, f_tu_mpa=f_tu, sigma_v_mpa=sv,
                             strength_mpa=np.minimum(joint, brick_eq) * (1 + error),
                             failure_mode=np.where(joint <= brick_eq, "joint", "brick")))


def test_a_predictor_scores_zero_on_the_runs_it_made_and_its_bias_when_they_are_off():
    """A format's constant brick fills the inputs its runs lack; runs made
    by the predictor score MAPE 0 and every mode right; runs 10 % stronger,
    MAPE 100 (1 - 1/1.1) % and bias -9.09 %."""
    uk = dict(L=215.0, H=65.0, W=102.5, t=10.0)
    s = F.scores(_runs(200, uk, 1), PREDICTOR, uk, "nonspatial")
    assert s["runs"] == 200 and s["mape_pct"] == pytest.approx(0.0, abs=1e-9) and s["mode_agreement"] == 1.0
    s = F.scores(_runs(200, uk, 1, error=0.1), PREDICTOR, uk, "nonspatial")
    assert s["mape_pct"] == pytest.approx(100 * (1 - 1 / 1.1)) and s["bias_pct"] == pytest.approx(-100 / 11)
    # the in-sample runs carry their own brick in columns; a format with a predictor of its own is scored by both
    fitted = _runs(50, uk, 2).assign(L_mm=uk["L"], H_mm=uk["H"], t_mm=uk["t"])
    df = dict(L=240.0, H=52.0, W=115.0, t=12.0)
    t = F.held_out_table(PREDICTOR, {"uk": (_runs(40, uk, 3), uk, "nonspatial", None),
                                     "df": (_runs(40, df, 4), df, "nonspatial", PREDICTOR)}, fitted)
    assert t.format.tolist() == ["fitted (in sample)", "uk", "df"] and (t.mape_pct.abs() < 1e-9).all()
    assert np.isnan(t.own_mape_pct[1]) and t.own_mape_pct[2] == pytest.approx(0.0, abs=1e-9)
    text = F.caption_values(t, ["joint failure: ..."])["lines"]
    assert "uk (215 x 102.5 x 65 mm, 10 mm joints; 40 runs)" in text and "own fixed-geometry" in text


def test_a_format_is_scored_on_its_regression_variant_alone_and_mode_by_mode():
    """Runs of another variant (spatial ones, here 50 % off) do not count;
    runs whose failure mode the lower equation does not name (the first 10
    of 40 relabelled) lower the mode agreement to 30 / 40 exactly, and do
    not change the MAPE (scored on strength)."""
    uk = dict(L=215.0, H=65.0, W=102.5, t=10.0)
    runs = _runs(40, uk, 5)
    flipped = runs.copy()
    flipped.loc[:9, "failure_mode"] = np.where(flipped.failure_mode[:10] == "joint", "brick", "joint")
    spatial = _runs(40, uk, 6, error=0.5).assign(variant="spatial")
    s = F.scores(pd.concat([flipped, spatial], ignore_index=True), PREDICTOR, uk, "nonspatial")
    assert s["runs"] == 40 and s["mode_agreement"] == 30 / 40
    assert s["mape_pct"] == pytest.approx(0.0, abs=1e-9)
    s = F.scores(pd.concat([runs, spatial], ignore_index=True), PREDICTOR, uk, "spatial")
    assert s["runs"] == 40 and s["mape_pct"] == pytest.approx(100 * (1 - 1 / 1.5))
