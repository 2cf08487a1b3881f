"""From samples to scenes: the study's dependent rules reach the model."""
import numpy as np
import pytest

from masonrydem.dem import kernels as K
from masonrydem.study.sampling import study_samples
from masonrydem.scene import joint_kn
from masonrydem.specimen.build import build
from masonrydem.scene import build_scene
from masonrydem.study.settings import record, settings

# the source paper's elasto-plastic units, whose zones carry the unit's properties
BASE = "config/scenes/willis.yaml"
OVERRIDES = ["physics.blocks=elasto-plastic", "numerics.cells=[3, 1, 1]"]


def _pressure(sigma_v):
    """The precompression sigma_v (Pa) as an override."""
    return f"loading.precompression.pressure={sigma_v!r}"


def _scene(study, s, variant, sigma_v):
    """The typed scene of a study's sample record at a precompression."""
    rec = record(s, study.variants[variant]["draw"], study.variables, study.rules)
    return build_scene(BASE, OVERRIDES + [_pressure(sigma_v)], rec["settings"], f"{variant}:s{s['sample']}")


def test_nonspatial_sample_reaches_every_zone_and_joint(willis):
    """One value per variable for the whole wallette: zones get E_b, f_tu,
    c_u = 1.5 f_tu and G_fu = 40 (f_tu/MPa)^0.7 N/m; joints get f_tj,
    c_j = 1.2 f_tj, w_u = 2 G_I / f_t = 2 x 0.03e-3 m (G_I = 0.03 f_tj),
    s_u = 2 G_II / c = 2 x 10 x 0.03e-3 / 1.2 m, tan(phi_j), k_n(E_b)."""
    s = dict(sample=3, f_tj=0.25e6, f_tu=4.2e6, phi_j=33.0, E_b=12e9)
    sp = build(_scene(willis, s, "nonspatial", 0.25e6))
    b = sp.assembly
    zp, jp = b.zones.par, b.joints.par
    G = 12e9 / 2.4
    np.testing.assert_allclose(zp[:, K.ZP_G], G)
    np.testing.assert_allclose(zp[:, K.ZP_FT], 4.2e6)
    np.testing.assert_allclose(zp[:, K.ZP_C], 1.5 * 4.2e6)
    np.testing.assert_allclose(zp[:, K.ZP_GF], 40.0 * 4.2 ** 0.7)
    np.testing.assert_allclose(jp[:, K.JP_FT], 0.25e6)
    np.testing.assert_allclose(jp[:, K.JP_C], 1.2 * 0.25e6)
    np.testing.assert_allclose(jp[:, K.JP_WU], 2 * 0.03e-3)
    np.testing.assert_allclose(jp[:, K.JP_SU], 2 * 10 * 0.03e-3 / 1.2)
    np.testing.assert_allclose(jp[:, K.JP_TANPHI], np.tan(np.radians(33.0)))
    np.testing.assert_allclose(jp[:, K.JP_KN], joint_kn(12e9, 0.1, 0.01))
    assert sp.scene.loading.precompression.pressure == 0.25e6


def test_spatial_sample_per_unit_and_joint(willis):
    """Spatial: unit u's zones carry its own E_b, f_tu and G_fu(f_tu);
    joint j's sub-contacts its own f_tj, phi_j and G_I(f_tj)."""
    _, spatial, _ = study_samples(2, 11, 24, 38, willis.variables, willis.correlations)
    s = spatial.iloc[1]
    sp = build(_scene(willis, s.to_dict(), "spatial", 0.0))
    b = sp.assembly
    start = 0
    for blk in b.blocks:
        n = blk.mesh.tets.shape[0]
        zp = b.zones.par[start:start + n]
        np.testing.assert_allclose(zp[:, K.ZP_FT], s["f_tu"][blk.id])
        np.testing.assert_allclose(zp[:, K.ZP_GF], 40.0 * (s["f_tu"][blk.id] / 1e6) ** 0.7)
        np.testing.assert_allclose(zp[:, K.ZP_G], s["E_b"][blk.id] / 2.4)
        start += n
    jp = b.joints.par
    for c, j in zip(b.contacts, sp.contact_joint):
        np.testing.assert_allclose(jp[c.sc, K.JP_FT], s["f_tj"][j])
        np.testing.assert_allclose(jp[c.sc, K.JP_WU], 2 * 0.03e-3)
        np.testing.assert_allclose(jp[c.sc, K.JP_TANPHI], np.tan(np.radians(s["phi_j"][j])))


def test_unknown_draw(willis):
    with pytest.raises(ValueError):
        settings(dict(sample=0), "mixed", willis.variables, willis.rules)
