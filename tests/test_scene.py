"""Scenes: validation before any computation, overrides, numbering and the
per-unit / per-joint properties."""
import numpy as np
import pandas as pd
import pytest

from masonrydem.errors import InputError
from masonrydem.dem import kernels as K
from masonrydem.scene import joint_kn
from masonrydem.scene import build_scene, validate_scene
from masonrydem.specimen.build import build

WILLIS = "config/scenes/willis.yaml"
# one block per unit (no crack interfaces), as these numbering tests count
ONE_BLOCK_PER_UNIT = {"physics.blocks": "elasto-plastic", "numerics.cells": [5, 2, 2], "numerics.subcontact_refine": 1}


def test_willis_scene_is_the_study_specimen():
    """docs/study.md 1-3: modelled unit 240 x 114 x 75 mm, 24 units, 38 joints,
    wall 1080 x 114 x 450 mm, k_n = E_b E_m/(t(E_b - E_m)) = 166.7 GPa/m,
    k_s = 0.4 k_n, shear span a = 275 mm (elastic units: the joints without
    the potential-crack units' crack interfaces)."""
    sp = build(build_scene(WILLIS, ["physics.blocks=elastic"]))
    x = sp.assembly.nodes.x0[sp.assembly.block_of_node >= 0]
    assert np.ptp(x, axis=0) == pytest.approx([1.080, 0.114, 0.450])
    assert len(sp.units) == 24 and len(sp.joints) == 38
    kn = sp.assembly.joints.par[:, K.JP_KN]
    np.testing.assert_allclose(kn, 15e9 * 1.5e9 / (0.01 * 13.5e9))
    assert kn[0] == pytest.approx(166.7e9, rel=1e-3)
    assert sp.scene.loading.bending.shear_span == pytest.approx(0.275)


@pytest.mark.parametrize("override, field", [
    ("loading.bending.rate=-1", "loading.bending.rate"),
    ("numerics.cells=[4, 2]", "numerics.cells"),
    ("numerics.cells=[4, 0, 2]", "numerics.cells.1"),
    ("materials.units.nu=0.5", "materials.units.nu"),
    ("materials.units.E=0", "materials.units.E"),
    ("materials.joints.phi=95", "materials.joints.phi"),
    ("physics.joints=mohr", "physics.joints"),
    ("geometry.courses=0", "geometry.courses"),
    ("loading.bending.loads_x=[1.5]", "loading.bending.loads_x.0"),
    ("materials.per_unit.E=[1.0e9, 2.0e9]", "materials.per_unit.E"),
    ("numerics.celss=[4, 2, 2]", "numerics"),
    ("outputs.crack_through=2", "outputs.crack_through"),
    ("geometry.joint_thickness=0", "geometry.joint_thickness"),
    ("physics.displacements=large", "physics.displacements"),   # deformable blocks are small-displacement
    ("physics.blocks=plastic", "physics.blocks"),
])
def test_bad_scene_refused_naming_the_field(override, field):
    with pytest.raises(InputError) as e:
        build_scene(WILLIS, [override])
    assert e.value.field == field


def test_overrides_parse_values():
    sc = build_scene(WILLIS, ["materials.units.E=12e9", "numerics.cells=[3, 1, 1]", "name=x"])
    assert np.all(sc.materials.units.E == 12e9) and sc.discretization.cells == (3, 1, 1)
    with pytest.raises(InputError, match="--set"):
        build_scene(WILLIS, ["numerics.cells"])


def test_missing_scene_file_refused():
    with pytest.raises(InputError, match="cannot read"):
        build_scene("config/scenes/nope.yaml")


def test_joint_numbering_and_per_joint_values():
    """Head joints first (3 per course), then the bed-joint plane under each
    unit of courses 1-5; a bed plane touching two lower units is one joint.
    Per-joint f_tj reach exactly the sub-contacts of their joint."""
    ft = np.linspace(0.1e6, 0.8e6, 38)
    sc = build_scene(WILLIS, settings={**ONE_BLOCK_PER_UNIT, "materials.per_joint.ft": ft.tolist(),
                                       "materials.joints.GI_per_ft": 3.0e-5})
    sp = build(sc)
    a, par = sp.assembly, sp.assembly.joints.par
    for c, j in zip(a.contacts, sp.contact_joint):
        ua, ub = sp.units[sp.block_unit[c.block_a]], sp.units[sp.block_unit[c.block_b]]
        kind, unit = sp.joints[j]
        if kind == "head":
            assert ua[0] == ub[0] == unit[0] and min(ua[1], ub[1]) == unit[1]
        else:
            assert unit == max(ua, ub) and abs(ua[0] - ub[0]) == 1
        np.testing.assert_allclose(par[c.sc, K.JP_FT], ft[j])
        # G_I = 0.03 f_tj (N/mm, MPa) = 3e-5 f_tj (N/m, Pa): w_u = 2 G_I / f_t = 6e-5 m
        np.testing.assert_allclose(par[c.sc, K.JP_WU], 6e-5)
    counts = np.bincount(sp.contact_joint, minlength=38)
    assert counts[:18].tolist() == [1] * 18
    assert sorted(set(counts[18:].tolist())) == [1, 2]     # end units of odd courses touch one


def test_joint_stiffness_follows_mean_unit_modulus():
    """A joint's k_n uses the mean E_b of the two units it connects."""
    E = np.where(np.arange(24) % 2, 10e9, 20e9)
    sp = build(build_scene(WILLIS, settings={**ONE_BLOCK_PER_UNIT, "materials.per_unit.E": E.tolist()}))
    par = sp.assembly.joints.par
    for c in sp.assembly.contacts:
        expected = joint_kn(0.5 * (E[c.block_a] + E[c.block_b]), 0.1, 0.01)
        np.testing.assert_allclose(par[c.sc, K.JP_KN], expected)


def test_rigid_units_refuse_a_final_state_and_build_without_zones():
    """Rigid units have no zones to write (outputs.state refused, naming the
    field); the wallette with rigid units builds one node per unit and the
    joints of the deformable one."""
    with pytest.raises(InputError) as e:
        build_scene(WILLIS, ["physics.blocks=rigid", "outputs.state=true"])
    assert e.value.field == "outputs.state"
    rigid = build(build_scene(WILLIS, ["physics.blocks=rigid"]))
    full = build(build_scene(WILLIS, ["physics.blocks=elastic"]))
    assert int((rigid.assembly.block_of_node >= 0).sum()) == 24 and rigid.assembly.zones.tets.shape[0] == 0
    assert len(rigid.assembly.contacts) == len(full.assembly.contacts)
    np.testing.assert_array_equal(rigid.contact_joint, full.contact_joint)


@pytest.mark.parametrize("spreader", [True, False])
def test_precompression_force_and_where_it_acts(spreader):
    """The vertical force on the top course is sigma_v times its plan area
    (960 x 114 mm) either way.  As a uniform pressure on the whole top face,
    the force on the end unit of the toothed top course (x 840-1080 mm)
    acts at x = 960 mm, on the edge of the course below: neutral
    equilibrium.  With the spreader it acts where the top course bears on
    the course below, x 120-960 mm, at sigma_v 960 / 840, and the end
    unit's resultant lies at x = 900 mm, inside its bearing.  The nodal
    forces are consistent (a rule exact for the faces' bilinear fields),
    so the resultant of the whole load acts at the middle of the loaded
    span, 540 or 600 mm, whatever the mesh."""
    sigma = 0.5e6
    sp = build(build_scene(WILLIS, [f"loading.precompression.pressure={sigma}",
                                   f"loading.precompression.spreader={str(spreader).lower()}"]))
    b = sp.assembly
    fz, x = b.nodes.fext[:, 2], b.nodes.x0[:, 0]
    assert fz.sum() == pytest.approx(-sigma * 0.960 * 0.114, rel=1e-12)
    assert np.sum(fz * x) / np.sum(fz) == pytest.approx(0.540 if spreader else 0.600, abs=1e-9)
    end = np.isin(b.block_of_node, np.flatnonzero(sp.block_unit == sp.units.index((5, 3))))   # its blocks
    assert np.sum(fz[end] * x[end]) / np.sum(fz[end]) == pytest.approx(0.900 if spreader else 0.960, abs=1e-9)


def test_a_scene_without_numerics_runs_at_the_accuracy_studys_choice(tmp_path):
    """One source of numerical defaults: the accuracy study's 'default'
    setting is the study's scene with no numerics of its own, so the
    schema's defaults are what it measured.  The candidates next to it (config.yaml: pc_c4x3x2_r1 is the defaults with
    subcontact_refine=1) name the same cells, and the rates tried around
    it are set by its rate.  A scene that says nothing about its physics,
    numerics or loading rates gets exactly what the Willis scene runs
    (docs/accuracy.md)."""
    import yaml
    raw = yaml.safe_load(open(WILLIS))
    assert "numerics" not in raw
    bare = {k: v for k, v in raw.items() if k != "physics"}
    for key in ("rate", "ramp_steps"):
        del bare["loading"]["bending"][key]
    del bare["loading"]["precompression"]["ratio_tol"]
    sc = build_scene(bare)
    assert sc.physics.blocks == "potential-crack"
    assert sc.discretization == build_scene(WILLIS).discretization and sc.integration == build_scene(WILLIS).integration
    # what the accuracy study ran as its 'default' setting (config.yaml):
    # the candidate pc_c4x3x2_r1 is these cells with sub-contacts unrefined,
    # pc_c4x3x2_head_rate15 them at 1.5 times the rate, and the rates tried
    # around the defaults are half and twice it; its choice (choice.csv) is
    # that default, within the 2 % of its references
    acc = yaml.safe_load(open("config/config.yaml"))["accuracy"]
    cand = {c["name"]: dict(o.split("=", 1) for o in c["overrides"]) for c in acc["candidates"]}
    assert [int(x) for x in cand["pc_c4x3x2_r1"]["numerics.cells"].strip("[]").split(",")] == list(sc.discretization.cells)
    rate = sc.loading.drive.rate
    assert float(cand["pc_c4x3x2_head_rate15"]["loading.bending.rate"]) == pytest.approx(1.5 * rate, rel=1e-12)
    tried = next(x["values"] for x in acc["settings"] if x["key"] == "loading.bending.rate")
    assert tried == pytest.approx([rate / 2, rate * 2], rel=1e-12)
    choice = pd.read_csv("results/accuracy/choice.csv").set_index("setting")
    assert choice.loc["default", "default"] and choice.loc["default", "ok"]
    assert choice.loc["default", "max_abs_error"] <= acc["tolerance"]


def test_a_scene_must_state_its_specimen():
    """No study's wallette is a default: a scene without its brick, its
    materials or where its test bears is refused, naming what is missing."""
    import yaml
    raw = yaml.safe_load(open(WILLIS))
    for path, field in ((("geometry", "unit"), "geometry"), (("materials", "units", "E"), "materials.units"),
                        (("materials", "joints", "GI"), "materials.joints.GI"),
                        (("loading", "bending", "supports_x"), "loading.bending.supports_x")):
        bare = yaml.safe_load(open(WILLIS))
        node = bare
        for key in path[:-1]:
            node = node[key]
        del node[path[-1]]
        with pytest.raises(InputError) as e:
            build_scene(bare)
        assert e.value.field == field, (path, str(e.value))
    assert build_scene(raw).name == "willis"
