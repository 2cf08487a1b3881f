"""Point tests of the constitutive laws (kernels.zones, laws.py): the
Mohr-Coulomb return mapping and its elastic pre-check, and the tables of
laws.  Each test states its formula and tolerance."""
import math

import numpy as np
import pytest

from masonrydem.dem import JointProps, MohrCoulomb
from masonrydem.errors import InputError
from masonrydem.dem import kernels as K
from masonrydem.dem.kernels.joint_laws import _JOINT_LAWS
from masonrydem.dem.kernels.zones import mohr_coulomb_elastic, zone_mohr_coulomb
from masonrydem.dem.laws import JOINT_LAWS
from masonrydem.scene import BLOCK_MODELS
from masonrydem.specimen.build import MATERIALS
from masonrydem.scene import SCHEMA

pytestmark = pytest.mark.verification

MAT = MohrCoulomb(E=15e9, nu=0.2, ft=3.0e6, c=4.5e6, phi=35.0, Gf=100.0)
NPHI = (1 + math.sin(math.radians(35.0))) / (1 - math.sin(math.radians(35.0)))


def _principal(s):
    t = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
    return np.linalg.eigvalsh(t)


def _random_stresses(n, seed, scale):
    """Random symmetric stresses (xx, yy, zz, xy, yz, zx) of magnitude ``scale``."""
    rng = np.random.default_rng(seed)
    return scale * rng.standard_normal((n, 6))


def _trials(n, seed, increment, shift=0.0):
    """Elastic trials as the solver makes them: a stress on the yield
    surface (random axes; half on the shear surface with s3 uniform in
    [-20 MPa, f_t] + shift, half on the cut-off s3 = f_t when the shift is
    0) plus a random increment of magnitude ``increment``."""
    rng = np.random.default_rng(seed)
    ft, c = MAT.row()[K.ZP_FT], MAT.c
    rows = []
    while len(rows) < n:
        if shift or rng.uniform() < 0.5:
            p3 = rng.uniform(-20e6, ft) + shift
            p1 = p3 * NPHI - 2 * c * math.sqrt(NPHI)
        else:
            p3 = ft
            p1 = rng.uniform(ft * NPHI - 2 * c * math.sqrt(NPHI), ft)
        p = np.array([p1, rng.uniform(p1, p3), p3])
        q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
        t = q @ np.diag(p) @ q.T
        rows.append([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[1, 2], t[0, 2]])
    return np.array(rows) + increment * rng.standard_normal((n, 6))


def _correct(stress, mat=MAT):
    """Runs the return mapping on each row; returns (corrected stresses,
    yielded flags, states).  A unit cube cell (crack band h = 1 m)."""
    n = stress.shape[0]
    zp = np.tile(mat.row(), (n, 1))
    zs = np.zeros((n, K.N_ZS))
    st = stress.copy()
    x0 = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], float)
    gnodes = np.arange(8, dtype=np.int64)
    a, v = np.zeros((3, 3)), np.zeros((3, 3))
    yielded = np.array([zone_mohr_coulomb(t, zp, zs, st, a, v, x0, gnodes, 0, 8) for t in range(n)])
    return st, yielded, zs


def _tensor(s):
    return np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])


def test_return_mapping_lands_on_the_yield_surface():
    """The correction is coaxial (the corrected stress has the trial's
    principal axes: off-diagonal terms below 1e-9 of the stress in that
    frame) and lands on the surface it returns to: from an uncracked
    state, a trial that yielded in shear ends on
    f_s = s1 - s3 N_phi + 2 c sqrt(N_phi) = 0 (s1, s3 along the trial's
    extreme principal axes; to 1e-9 of c), one that yielded in tension
    on the cut-off s3 = f_t (to 1e-9 of f_t; the strength softens from
    the next step, with the plastic strain this correction adds).  Trials:
    stresses on the surface plus increments of 1 % of c, 20,000 of them.
    (It is FLAC's single-surface return, chosen by the h-function: a
    second principal stress beyond the cut-off in biaxial tension, or an
    edge of the pyramid crossed by a large increment, is corrected in the
    next step.)"""
    trials = _trials(20_000, 1, 0.01 * MAT.c)
    st, yielded, zs = _correct(trials)
    ft, c = MAT.row()[K.ZP_FT], MAT.c
    shear = tension = 0
    for s0, s, y, z in zip(trials, st, yielded, zs):
        if not y:
            continue
        _, q = np.linalg.eigh(_tensor(s0))
        d = q.T @ _tensor(s) @ q
        assert np.abs(d - np.diag(np.diag(d))).max() < 1e-9 * np.abs(d).max()
        s1, s3 = d[0, 0], d[2, 2]
        if z[K.ZS_EPT] > 0:
            tension += 1
            assert s3 == pytest.approx(ft, abs=1e-9 * ft)
        else:
            shear += 1
            assert s1 - s3 * NPHI + 2 * c * math.sqrt(NPHI) == pytest.approx(0.0, abs=1e-9 * c)
    assert shear > 3000 and tension > 3000


def test_shear_return_keeps_the_trace():
    """Zero dilation (N_psi = 1): the shear correction moves s1 and s3 by
    -+ 2 G lambda, so the mean stress is unchanged (to 1e-12 of the
    stress), and so is the stress along the trial's intermediate
    principal axis.  Trials on the
    shear surface in compression (shifted by -5 MPa, increments of 2 % of
    c) yield in shear only."""
    base = _trials(20_000, 2, 0.02 * MAT.c, shift=-5e6)
    st, yielded, zs = _correct(base)
    assert yielded.sum() > 5000 and np.all(zs[:, K.ZS_EPT] == 0.0)
    np.testing.assert_allclose(st[:, :3].sum(axis=1), base[:, :3].sum(axis=1), rtol=0, atol=1e-12 * 3e7)
    for s0, s in zip(base[yielded], st[yielded]):
        p, q = np.linalg.eigh(_tensor(s0))
        assert (q.T @ _tensor(s) @ q)[1, 1] == pytest.approx(p[1], abs=1e-9 * 3e7)


def test_elastic_precheck_never_passes_a_yielding_stress():
    """The cheap pre-check (invariant bounds on the extreme principal
    stresses) may send an elastic stress to the exact check, but never
    lets a stress outside the surface through: on 200,000 random
    stresses (scales from 0.3 to 30 MPa, shifted in mean stress), every
    one it passes has f_s >= 0 and s3 <= f_t."""
    zp = np.tile(MAT.row(), (1, 1))
    zs = np.zeros((1, K.N_ZS))
    ft, c = MAT.row()[K.ZP_FT], MAT.c
    passed = 0
    for seed, scale in enumerate((0.3e6, 1e6, 3e6, 10e6, 30e6)):
        stress = _random_stresses(40_000, 10 + seed, scale)
        stress[:, :3] += np.random.default_rng(seed).uniform(-3, 1, (40_000, 1)) * scale
        for s in stress:
            if mohr_coulomb_elastic(0, zp, zs, s[None, :]):
                passed += 1
                s1, _, s3 = _principal(s)
                assert s1 - s3 * NPHI + 2 * c * math.sqrt(NPHI) >= 0 and s3 <= ft
    assert 20_000 < passed < 190_000


def test_law_tables_drive_the_scene_schema_and_validation():
    """The scene's choices of physics are the tables' names (the scene
    lists the solver's joint laws by name, in the solver's order; every
    block model's material is one the specimen builder maps), and a law
    validates exactly the fields its table entry names: the friction law
    ignores the tensile strength, the coupled one needs G_I for it."""
    phys = SCHEMA["properties"]["physics"]["properties"]
    assert phys["joints"]["enum"] == list(JOINT_LAWS) and phys["blocks"]["enum"] == list(BLOCK_MODELS)
    assert {m.material for m in BLOCK_MODELS.values()} == set(MATERIALS)
    p = JointProps(kn=1e10, ks=4e9, ft=0.3e6, c=0.36e6, phi=35.0)
    p.validate("j", "friction")
    with pytest.raises(InputError, match="j.GI"):
        p.validate("j", "coupled_softening")
    # every kernel law (the bearing aside) has its entry in the table, and only those
    assert {law.id for law in JOINT_LAWS.values()} | {K.JOINT_BEARING} == set(_JOINT_LAWS)
