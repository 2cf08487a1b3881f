"""Scenes: a specimen described in YAML (inputs.py reads it), validated
once into a typed, frozen ``Scene`` (specimen.py builds it).

A scene (schema: scene_schema.yaml, defaults = the Willis wallette of
docs/study.md) declares geometry, physics, materials, loading, numerics and
outputs.  ``load_scene`` reads it, applies ``--set`` overrides and checks it;
every error names the field (a dotted path, as the scene writes it) and the
reason.  Refused before anything is allocated: a NaN or an infinity, a
value the schema does not allow, a test whose geometry makes no sense, and
a model too large for the machine's memory (``model_size``).  Nothing
below this module reads the scene as a mapping.
"""
import copy
import os
from dataclasses import dataclass, replace
from importlib import resources

from jsonschema import Draft202012Validator, validators

from .bending import check_loading, placed
from .blocks import refine_axes
from .errors import InputError, check_finite
from .inputs import apply_overrides, read_scene, read_yaml
from .laws import BLOCK_MODELS, JOINT_LAWS, Elastic, MohrCoulomb
from .masonry import Geometry, JointFields, UnitFields, joint_fields, unit_fields
from .quantities import check_plausible, convert

SCHEMA = read_yaml(resources.files(__package__).joinpath("scene_schema.yaml").read_text())
# the choices of physics come from the tables of laws (laws.py)
SCHEMA["properties"]["physics"]["properties"]["blocks"]["enum"] = list(BLOCK_MODELS)
SCHEMA["properties"]["physics"]["properties"]["joints"]["enum"] = list(JOINT_LAWS)


@dataclass(frozen=True)
class Physics:
    """The effects the scene declares (the solver runs nothing else)."""
    blocks: str           # laws.BLOCK_MODELS
    joints: str           # laws.JOINT_LAWS
    gravity: bool
    large: bool           # large displacements (rigid blocks only)

    @property
    def model(self):
        return BLOCK_MODELS[self.blocks]


@dataclass(frozen=True)
class Materials:
    units: UnitFields     # one value per unit
    joints: JointFields   # one value per mortar joint


@dataclass(frozen=True)
class Precompression:
    pressure: float       # sigma_v (Pa)
    spreader: bool
    platen: bool
    ratio_tol: float
    max_steps: int


@dataclass(frozen=True)
class Drive:
    """Displacement control of the test stage."""
    rate: float           # m per step
    ramp_steps: int
    max_displacement: float
    load_drop: float
    max_steps: int
    past_peak: tuple = None  # (drop, after, at_most): stops.Stops.past_peak


@dataclass(frozen=True)
class Bending:
    supports_x: tuple
    loads_x: tuple
    section_height: float
    strip_width: float
    strip_stiffness_ratio: float
    strips_turn: bool
    strip_friction: float

    @property
    def shear_span(self):
        """a: from the first support to the first load."""
        return min(self.loads_x) - min(self.supports_x)


@dataclass(frozen=True)
class Loading:
    test: str             # bending, tension or triplet
    precompression: Precompression
    drive: Drive          # the test's
    bending: Bending


@dataclass(frozen=True)
class Refine:
    """Sub-contact refinement per kind of contact, each per global axis."""
    head: tuple
    bed: tuple
    crack: tuple
    strips: tuple


@dataclass(frozen=True)
class Numerics:
    elastic_element: str
    cells: tuple
    refine: Refine
    refine_label: str     # as the rows record it: '2', '1x2x1' or 'head:1x2x1'
    rule: str             # the joints' sub-contact rule: simpson, or vertices (3DEC's)
    safety: float
    damping: float
    record_every: int


@dataclass(frozen=True)
class Outputs:
    curve_points: int
    state: bool
    crack_damage: float
    crack_through: float
    broken_joint_damage: float


@dataclass(frozen=True)
class Scene:
    name: str
    geometry: Geometry
    physics: Physics
    materials: Materials
    loading: Loading
    numerics: Numerics
    outputs: Outputs
    description: str = ""


def _with_defaults(cls):
    """A validator that fills in the schema's defaults while validating
    (the jsonschema FAQ recipe)."""
    validate_props = cls.VALIDATORS["properties"]

    def set_defaults(validator, properties, instance, schema):
        if isinstance(instance, dict):
            for key, sub in properties.items():
                if "default" in sub and key not in instance:
                    instance[key] = copy.deepcopy(sub["default"])
        yield from validate_props(validator, properties, instance, schema)

    return validators.extend(cls, {"properties": set_defaults})


_Validator = _with_defaults(Draft202012Validator)


def validate_scene(scene):
    """The typed Scene of a mapping (its defaults filled in place); raises
    InputError naming the first offending field."""
    if not isinstance(scene, dict):
        raise InputError("scene", "must be a mapping")
    written = convert(scene, SCHEMA)     # quantities ('0.15 MPa') to SI floats
    positioned = _given(scene, "loading", "bending") & {"supports_x", "loads_x"}    # before the defaults fill them in
    check_finite(scene)
    errors = sorted(_Validator(SCHEMA).iter_errors(scene), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        raise InputError(".".join(str(p) for p in e.absolute_path) or "scene", e.message)
    check_plausible(scene, SCHEMA, written)
    g, phys, num = _geometry(scene["geometry"]), _physics(scene["physics"]), _numerics(scene["numerics"])
    loading = _loading(scene["loading"], g, positioned)
    if phys.large and phys.blocks != "rigid":
        raise InputError("physics.displacements", "large displacements need rigid blocks: deformable blocks "
                         f"({phys.blocks}) are small-displacement (strains on the initial geometry)")
    if phys.blocks == "rigid" and scene["outputs"]["state"]:
        raise InputError("outputs.state", "the final state (VTK: zones and their damage) exists for deformable "
                         "blocks only, not for rigid ones")
    if scene["materials"]["units"]["psi"] and not phys.model.crack_interface:
        raise InputError("materials.units.psi", f"dilation is modelled on the crack interfaces of potential-crack "
                         f"units only; {phys.blocks} units have none")
    _check_size(g, phys, num, loading)   # before anything that takes time in proportion to the model's size
    if phys.model.material is MohrCoulomb and (reason := g.crack_band_error(num.cells[0])):
        raise InputError("numerics.cells.0", f"{reason} (the default cells are the potential-crack units'; "
                                             "elasto-plastic units come within 2 % on 15x7x5: docs/accuracy.md)")
    check_loading(g, loading)
    return Scene(name=scene["name"], description=scene.get("description", ""), geometry=g, physics=phys,
                 materials=_materials(scene["materials"], g), loading=loading, numerics=num,
                 outputs=Outputs(**scene["outputs"]))


def _given(scene, *path):
    """The keys a scene gives itself at a path of sections (none if absent)."""
    node = scene
    for key in path:
        node = node.get(key) if isinstance(node, dict) else None
    return set(node) if isinstance(node, dict) else set()


def load_scene(path, overrides=()):
    """The scene file at ``path`` with ``overrides`` ('path.to.key=value'),
    validated; InputError names the first offending field."""
    return validate_scene(apply_overrides(read_scene(path), overrides))


def _geometry(g):
    u = g["unit"]
    return Geometry(unit_length=u["length"], unit_height=u["height"], unit_width=u["width"],
                    joint_thickness=g["joint_thickness"], courses=g["courses"], units_per_course=g["units_per_course"],
                    bond_offset=g["bond_offset"])


def _physics(p):
    return Physics(blocks=p["blocks"], joints=p["joints"], gravity=p["gravity"], large=p["displacements"] == "large")


def _loading(lo, g, given=()):
    test = lo["test"]
    b = lo["bending"]
    supports, loads = placed(b, g, given) if test == "bending" else (tuple(b["supports_x"]), tuple(b["loads_x"]))
    drive = {k: lo[test][k] for k in ("rate", "ramp_steps", "max_displacement", "load_drop", "max_steps")}
    if (past := lo[test].get("past_peak")) is not None:
        drive["past_peak"] = (past["drop"], past["after"], past["at_most"])
    return Loading(test=test, precompression=Precompression(**lo["precompression"]), drive=Drive(**drive),
                   bending=Bending(supports_x=supports, loads_x=loads,
                                   section_height=b.get("section_height", g.built_height),
                                   strip_width=b["strip_width"],
                                   strip_stiffness_ratio=b["strip_stiffness_ratio"], strips_turn=b["strips_turn"],
                                   strip_friction=b["strip_friction"]))


KINDS = ("head", "bed", "crack", "strips")


def _numerics(n):
    raw = n["subcontact_refine"]
    per_kind = {k: raw.get(k, 1) for k in KINDS} if isinstance(raw, dict) else dict.fromkeys(KINDS, raw)
    refine = Refine(**{k: refine_axes(v) for k, v in per_kind.items()})
    return Numerics(elastic_element=n["elastic_element"], cells=tuple(n["cells"]), refine=refine,
                    refine_label=refine_label(raw), rule=n["subcontact_rule"], safety=n["safety"], damping=n["damping"],
                    record_every=n["record_every"])


def refine_label(refine):
    """A sub-contact refinement as the rows record it: '2', '1x2x1' per axis
    (as cells), or per kind of contact 'head:1x2x1,bed:1'."""
    if isinstance(refine, dict):
        return ",".join(f"{k}:{refine_label(v)}" for k, v in refine.items())
    return "x".join(str(r) for r in refine) if isinstance(refine, (list, tuple)) else str(refine)


def _field(section, per, key, n, what):
    """One value per unit or joint: the per-item list, else the wall's value."""
    values = per.get(key)
    if values is None:
        return [float(section[key])] * n
    if len(values) != n:
        raise InputError(f"materials.per_{what}.{key}", f"needs one value per {what} ({n} {what}s), "
                         f"got {len(values)}")
    return values


def _materials(m, g):
    """The units' and joints' fields by the rules of masonry.py: the same
    for a property given once for the wall and one given per item."""
    mu, mj = m["units"], m["joints"]
    per_u, per_j = m.get("per_unit", {}), m.get("per_joint", {})
    n_units, n_joints = g.n_units, len(g.joints)
    rule = mu.get("Gf_rule")
    units = unit_fields(E=_field(mu, per_u, "E", n_units, "unit"), ft=_field(mu, per_u, "ft", n_units, "unit"),
                        nu=mu["nu"], c_ratio=mu["c_ratio"], phi=mu["phi"], psi=mu["psi"], Gf=mu["Gf"],
                        density=mu["density"],
                        crack_kn_ratio=mu["crack_kn_ratio"],
                        gf_rule=(rule["coefficient"], rule["exponent"]) if rule else None)
    joints = joint_fields(ft=_field(mj, per_j, "ft", n_joints, "joint"), phi=_field(mj, per_j, "phi", n_joints, "joint"),
                          c_ratio=mj["c_ratio"], GI=mj["GI"], GII_ratio=mj["GII_ratio"], Em_ratio=mj["Em_ratio"],
                          ks_ratio=mj["ks_ratio"], gi_per_ft=mj.get("GI_per_ft"),
                          residual_friction_ratio=mj["residual_friction_ratio"])
    return Materials(units=units, joints=joints)


# bytes per item of a model at the peak of building it and setting up its
# solver, measured on the wallette and rounded up (9 x 4 x 3 cells: 25,920
# tetrahedra and 7,119 sub-contacts, 80 MB; rigid units at refine 4: 29,597
# sub-contacts, 34 MB; potential-crack hex8i 4 x 4 x 3, refine 2: 1,152
# cells and 14,637 sub-contacts, 17 MB)
ITEM_BYTES = dict(nodes=500, tetrahedra=3000, cells=5000, sub_contacts=1500)


def model_size(g, physics, numerics, loading):
    """An upper estimate of the model a scene builds, from its numbers alone
    (nothing allocated): nodes, tetrahedra (zones), linear cells,
    sub-contacts (joints, crack interfaces and strips: composite Simpson
    points, 2 r + 1 per interval and direction at refine r) and bytes
    (ITEM_BYTES)."""
    model = physics.model
    units = g.n_units
    r = numerics.refine
    pieces = 2 if model.crack_interface else 1
    a, b, c = max(numerics.cells[0], pieces), numerics.cells[1], numerics.cells[2]

    def simpson(m, rm, n, rn):      # points on a face of m x n intervals, refined rm and rn times
        return (2 * rm * m + 1) * (2 * rn * n + 1)

    bend = loading.bending
    strips = len(bend.supports_x) + len(bend.loads_x) if loading.test == "bending" else 0
    # per unit a head joint (and its crack interface) and a bed joint on the
    # union of two face grids, offset by the bond (their lines coincide when
    # the offset falls on a grid line); strips across the wall's height, a
    # few cells wide.  Faces normal to x: (y, z); to z: (x, y); strips (normal to y): (z, x)
    shift = g.bond_offset * a
    along = a if abs(shift - round(shift)) < 1e-9 else 2 * a
    subs = (units * (simpson(b, r.head[1], c, r.head[2]) + (pieces - 1) * simpson(b, r.crack[1], c, r.crack[2])
                     + simpson(along, r.bed[0], b, r.bed[1]))
            + strips * simpson(g.courses * c, r.strips[2], 3, r.strips[0]))
    # a platen: one node, and sub-contacts on the top course's faces
    platen = bool(loading.precompression.platen and loading.precompression.pressure)
    subs += platen * g.units_per_course * simpson(along, r.strips[0], b, r.strips[1])
    hexes = 0 if model.rigid else units * a * b * c
    zones = model.material is not Elastic or numerics.elastic_element == "zones"
    turns = strips if bend.strips_turn and not model.rigid else 0     # a turning strip's second node
    size = dict(nodes=strips + turns + platen + units * (pieces if model.rigid else (a + pieces) * (b + 1) * (c + 1)),
                tetrahedra=10 * hexes if zones else 0, cells=0 if zones else hexes, sub_contacts=subs)
    size["bytes"] = sum(ITEM_BYTES[k] * n for k, n in size.items())
    return size


def memory_bytes():
    """The machine's physical memory, or None if unknown."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def _check_size(g, physics, numerics, loading):
    """Refuses a model that would not fit in the machine's memory (it would
    end in a MemoryError after seconds or minutes of building), naming the
    setting to blame: the wall if it is too large at the schema's default
    cells and refinement, else the cells if too many at refinement 1, else
    the refinement."""
    memory = memory_bytes()
    size = model_size(g, physics, numerics, loading)
    if memory is None or size["bytes"] <= memory:
        return
    defaults = _numerics(copy.deepcopy({k: v["default"] for k, v in
                                        SCHEMA["properties"]["numerics"]["properties"].items()}))

    def fits(num):
        return model_size(g, physics, num, loading)["bytes"] <= memory

    if not fits(replace(numerics, cells=defaults.cells, refine=defaults.refine)):
        field = "geometry.courses" if g.courses >= g.units_per_course else "geometry.units_per_course"
    else:
        field = "numerics.subcontact_refine" if fits(replace(numerics, refine=defaults.refine)) else "numerics.cells"
    raise InputError(field, f"the model would need an estimated {_big(size['bytes'], 1e9)} GB of memory, more "
                     f"than this machine's {memory / 1e9:.3g} GB: {_big(size['tetrahedra'])} tetrahedra, "
                     f"{_big(size['cells'])} linear cells and {_big(size['sub_contacts'])} sub-contacts for "
                     f"{_big(g.n_units)} units (geometry.courses {g.courses} x geometry.units_per_course "
                     f"{g.units_per_course}) at numerics.cells {list(numerics.cells)} and "
                     f"numerics.subcontact_refine {numerics.refine_label}; use fewer cells, a lower refinement or "
                     "a smaller wall")


def _big(n, unit=1):
    return f"{n / unit:.3g}" if n < 10 ** 300 else f"over {1e300 / unit:.3g}"
