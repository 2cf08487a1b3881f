"""Quantities with units in a scene and on the command line, and
the plausible ranges of masonry.  A corpus of values as users write them:
in the units engineers think in (converted to SI, to the last digit), as
plain numbers meant in those units (refused, naming the unit meant), and
beyond any masonry (refused)."""
import copy
import dataclasses
import subprocess
import sys

import numpy as np
import pytest

from masonrydem.errors import InputError
from masonrydem.scene import apply_overrides, read_scene
from masonrydem.scene import validate_scene

WILLIS = "config/scenes/willis.yaml"

# (setting, value as written, the SI value it must give: the float that
# Python reads from the SI number written out, so equal to the last digit)
CONVERTED = [
    ("loading.precompression.pressure", "0.15 MPa", float("150000")),
    ("loading.precompression.pressure", "150 kPa", float("150000")),
    ("loading.precompression.pressure", "0.075 N/mm^2", float("75000")),
    ("materials.units.E", "15 GPa", float("15e9")),
    ("materials.units.E", "15000 MPa", float("15e9")),
    ("materials.units.ft", "3.75 MPa", float("3.75e6")),
    ("materials.joints.ft", "0.3 MPa", float("0.3e6")),
    ("materials.joints.GI", "0.009 N/mm", float("9")),
    ("materials.joints.GI", "9 J/m^2", float("9")),
    ("materials.units.Gf", "0.1 N/mm", float("100")),
    ("materials.joints.GI_per_ft", "0.03 mm", float("3e-5")),
    ("geometry.unit.length", "230 mm", float("0.23")),
    ("geometry.unit.height", "6.5 cm", float("0.065")),
    ("geometry.joint_thickness", "10 mm", float("0.01")),
    ("materials.units.density", "1.9 t/m^3", float("1900")),
    ("materials.units.density", "1900 kg/m^3", float("1900")),
    ("materials.joints.phi", "35 deg", float("35")),
    ("loading.bending.strip_width", "2 cm", float("0.02")),
    ("loading.bending.rate", "0.05 um", float("5e-8")),
    ("materials.joints.ks_ratio", "40 %", float("0.4")),
]


def _scene(*overrides):
    return validate_scene(apply_overrides(read_scene(WILLIS), list(overrides)))


def _raw(*overrides):
    return apply_overrides(read_scene(WILLIS), list(overrides))


def _same(a, b):
    """Two typed scenes equal to the last digit, arrays included."""
    if dataclasses.is_dataclass(a):
        return type(a) is type(b) and all(_same(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("key,written,si", CONVERTED, ids=[f"{k}={w}" for k, w, _ in CONVERTED])
def test_a_quantity_gives_the_scene_of_its_si_number(key, written, si):
    raw = _raw(f"{key}={written}")
    with_units = validate_scene(raw)
    node = raw
    for k in key.split("."):
        node = node[k]
    assert node == si and type(node) is float          # the value itself, to the last digit
    assert _same(with_units, _scene(f"{key}={si!r}"))    # and everything built from it


def test_the_angle_in_radians_converts_exactly_as_by_hand():
    raw = _raw("materials.joints.phi=0.6 rad")
    validate_scene(raw)
    assert raw["materials"]["joints"]["phi"] == pytest.approx(np.degrees(0.6), rel=1e-15)


# (setting, plain number meant in another unit, the unit the refusal names)
MEANT = [
    ("loading.precompression.pressure", "0.15", "0.15 MPa"),
    ("loading.precompression.pressure", "150", "150 kPa"),
    ("materials.units.E", "15", "15 GPa"),
    ("materials.units.E", "15000", "15000 MPa"),
    ("materials.units.ft", "3.5", "3.5 MPa"),
    ("materials.joints.ft", "0.3", "0.3 MPa"),
    ("geometry.unit.length", "230", "230 mm"),
    ("geometry.unit.height", "65", "65 mm"),
    ("geometry.joint_thickness", "10", "10 mm"),
    ("loading.bending.supports_x", "[135, 945]", "135 mm"),
    ("materials.joints.GI", "0.009", "0.009 N/mm"),
    ("materials.joints.GI_per_ft", "0.03", "0.03 mm"),
    ("materials.units.density", "1.9", "1.9 t/m^3"),
    ("materials.units.phi", "0.6", "0.6 rad"),
]


@pytest.mark.parametrize("key,plain,meant", MEANT, ids=[f"{k}={p}" for k, p, _ in MEANT])
def test_a_plain_number_meant_in_other_units_is_refused_naming_the_unit(key, plain, meant):
    with pytest.raises(InputError) as e:
        _scene(f"{key}={plain}")
    assert e.value.field.startswith(key)
    assert f"did you mean {meant}?" in e.value.reason
    assert "plausible range for masonry" in e.value.reason


# values beyond any masonry, in any unit: refused, with no unit to suggest
BEYOND = [
    ("materials.units.E", "15e12"),          # 15 TPa: steel is 0.2 TPa
    ("materials.units.E", "1 MPa"),          # rubber
    ("materials.units.ft", "300 MPa"),
    ("materials.joints.ft", "50 MPa"),
    ("geometry.unit.length", "5 m"),
    ("geometry.joint_thickness", "0.1 mm"),
    ("materials.units.density", "8000 kg/m^3"),
    ("loading.precompression.pressure", "200 MPa"),
    ("materials.joints.phi", "80"),
]


@pytest.mark.parametrize("key,value", BEYOND, ids=[f"{k}={v}" for k, v in BEYOND])
def test_a_value_beyond_any_masonry_is_refused(key, value):
    with pytest.raises(InputError) as e:
        _scene(f"{key}={value}")
    assert e.value.field == key
    assert "plausible range for masonry" in e.value.reason and "did you mean" not in e.value.reason


# quantities that are not quantities of the setting
WRONG = [
    ("loading.precompression.pressure", "0.15 mm", "a length", "a stress"),
    ("loading.precompression.pressure", "0.15 MP", "megapoise", "a stress"),
    ("materials.units.nu", "0.2 MPa", "a stress", "a ratio"),
    ("materials.joints.phi", "35 N", "newton", "an angle"),
    ("materials.units.E", "fifteen GPa", "not a quantity", None),
    ("materials.units.E", "15 GPA", "not a quantity", None),
]


@pytest.mark.parametrize("key,value,read,wanted", WRONG, ids=[f"{k}={v}" for k, v, _, _ in WRONG])
def test_a_quantity_of_another_kind_is_refused(key, value, read, wanted):
    with pytest.raises(InputError) as e:
        _scene(f"{key}={value}")
    assert e.value.field == key
    assert read in e.value.reason and (wanted is None or wanted in e.value.reason)


def test_a_scene_widens_a_range_on_purpose():
    with pytest.raises(InputError):
        _scene("materials.units.E=50 MPa")
    scene = _scene("materials.units.E=50 MPa", "plausible={materials.units.E: [10 MPa, 100 GPa]}")
    assert scene.materials.units.E[0] == 50e6
    # per-item lists use the path without the index
    n = len(_scene().geometry.joints)
    ft = _raw(f"materials.per_joint.ft=[{', '.join(['8 MPa'] * n)}]")
    with pytest.raises(InputError) as e:
        validate_scene(copy.deepcopy(ft))
    assert e.value.field == "materials.per_joint.ft.0"
    ft["plausible"] = {"materials.per_joint.ft": ["0 MPa", "10 MPa"]}
    assert validate_scene(ft).materials.joints.ft[0] == 8e6


@pytest.mark.parametrize("plausible,field", [
    ("{materials.units.nu: [0, 1]}", "plausible.materials.units.nu"),       # a ratio with no range
    ("{materials.units.Ee: [0, 1]}", "plausible.materials.units.Ee"),
    ("{materials.units.E: [1 GPa]}", "plausible.materials.units.E"),
    ("{materials.units.E: [10 GPa, 1 GPa]}", "plausible.materials.units.E"),
    ("{materials.units.E: [1 m, 10 GPa]}", "plausible.materials.units.E.0"),
])
def test_a_widened_range_is_checked_as_any_setting(plausible, field):
    with pytest.raises(InputError) as e:
        _scene(f"plausible={plausible}")
    assert e.value.field == field


def test_the_command_line_refuses_a_unit_slip_with_exit_2_before_running(tmp_path):
    r = subprocess.run([sys.executable, "-m", "masonrydem.cli", "run", WILLIS, "--set",
                        "loading.precompression.pressure=0.15", "--out", str(tmp_path / "x")],
                       capture_output=True, text=True)
    assert r.returncode == 2
    assert "loading.precompression.pressure" in r.stderr and "did you mean 0.15 MPa?" in r.stderr
    assert not (tmp_path / "x").exists()          # refused before anything was written


def test_the_schema_names_a_unit_and_range_for_every_physical_field():
    """Every number with a physical dimension has its unit and plausible
    range (the dimensionless ones are bounded by the schema itself)."""
    from masonrydem.scene.quantities import _nodes
    from masonrydem.scene import SCHEMA
    scene = _raw()
    validate_scene(scene)                     # fills in every default, in place
    physical = {"E", "ft", "phi", "psi", "Gf", "density", "GI", "length", "height", "width", "joint_thickness",
                "pressure", "supports_x", "loads_x", "section_height", "strip_width", "rate", "max_displacement"}
    seen = set()
    for path, _, sub, _ in _nodes(scene, SCHEMA, ""):
        name = [p for p in path.split(".") if not p.isdigit()][-1]
        if name in physical:
            assert "unit" in sub and "plausible" in sub, path
            seen.add(name)
    assert seen == physical


@pytest.mark.parametrize("text", ["0.35 N/mm2", "0.35 N/mm²", "0.35 N/mm^2", "350 kN/m2", "350000 N/m²", "0.35MPa"])
def test_engineering_spellings_of_a_stress(text):
    """A stress as engineers write it reads as 0.35 MPa does, to the last
    digit (pint's decimal arithmetic: 0.35e6 exactly)."""
    from masonrydem.scene import to_si
    assert to_si(text, "Pa", "f") == to_si("0.35 MPa", "Pa", "f") == 0.35e6
