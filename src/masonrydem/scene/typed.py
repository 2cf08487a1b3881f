"""Scenes: a specimen described in YAML (files.read_scene reads it),
validated once into a typed, frozen ``Scene`` of plain data: numbers,
tuples and names (specimen.build maps it to the solver's types; nothing
here imports the solver).

A scene (schema: schema.yaml, with each setting's default) declares
geometry, physics, materials, loading, numerics and outputs.
``build_scene`` reads it, applies ``--set`` overrides and a study's
settings, and checks it; every error names the field (a dotted path, as the scene writes it) and the
reason.  Refused before anything is allocated: a NaN or an infinity, a
value the schema does not allow, a test whose geometry makes no sense, and
a model too large for the machine's memory (``model_size``).  Nothing
below this module reads the scene as a mapping.
"""
import copy
from dataclasses import dataclass
from importlib import resources

import numpy as np
from jsonschema import Draft202012Validator, validators

from .bending import AXES, check_loading, fill_vertical, placed, section_of, vertical_defaults
from ..errors import InputError, check_finite
from .files import apply_overrides, read_scene, read_yaml, set_value
from .masonry import Geometry, JointFields, UnitFields, joint_fields, unit_fields
from .quantities import check_plausible, convert, schema_at
from .size import check_size


@dataclass(frozen=True)
class BlockModel:
    """A block model a scene can declare (``physics.blocks``): its units'
    material by name (specimen.build maps it to the solver's class), rigid
    or deformable, and whether each unit is split at its crack plane by a
    potential-crack interface."""
    name: str
    material: str         # elastic, or mohr-coulomb (tension softening)
    rigid: bool
    crack_interface: bool = False

    @property
    def plastic(self):
        return self.material == "mohr-coulomb"


BLOCK_MODELS = {m.name: m for m in (
    BlockModel("rigid", "elastic", True),
    BlockModel("elastic", "elastic", False),
    BlockModel("elasto-plastic", "mohr-coulomb", False),
    BlockModel("potential-crack", "elastic", False, crack_interface=True),
)}

SCHEMA = read_yaml(resources.files(__package__).joinpath("schema.yaml").read_text())


VERTICAL_DEFAULTS = vertical_defaults(SCHEMA)
# the choices of block model come from the table above; the joint laws'
# names are the schema's own enum (the solver's dem.laws.JOINT_LAWS, a test
# checks that they are the same names)
SCHEMA["properties"]["physics"]["properties"]["blocks"]["enum"] = list(BLOCK_MODELS)


@dataclass(frozen=True)
class Physics:
    """The effects the scene declares (the solver runs nothing else)."""
    blocks: str           # BLOCK_MODELS
    joints: str           # the solver's joint law (dem.laws.JOINT_LAWS)
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
    supports: tuple       # positions along the span (m): x in horizontal bending, z in vertical
    loads: tuple
    section: float        # b in sigma = 6 M / (b h^2) (m)
    strip_width: float
    strip_stiffness_ratio: float
    strips_turn: bool
    strip_friction: float
    section_as_built: bool = True   # no section written: the wall's as built
    spans_in_units: bool = False    # the spans written in modelled units (shear_span_units)
    direction: str = "horizontal"   # or vertical (scene.bending.AXES)

    @property
    def shear_span(self):
        """a: from the first support to the first load."""
        return min(self.loads) - min(self.supports)

    @property
    def axis(self):
        """The global axis the span runs along (0: x, 2: z)."""
        return AXES[self.direction][0]


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
class Discretization:
    """The scene's numerics in space and in the record: cells per unit,
    sub-contacts and how often a run records its state.  (How the solver
    integrates, damping and safety: ``Integration``.)"""
    elastic_element: str
    cells: tuple
    refine: Refine
    refine_label: str     # as the rows record it: '2', '1x2x1' or 'head:1x2x1'
    rule: str             # the joints' sub-contact rule: simpson, or vertices (3DEC's)
    record_every: int


@dataclass(frozen=True)
class Integration:
    """How the solver integrates: local damping and the safety factor on
    the critical step (specimen.build makes them the solver's Numerics)."""
    damping: float
    safety: float


@dataclass(frozen=True)
class Outputs:
    curve_points: int
    state: bool
    crack_damage: float
    crack_through: float
    broken_joint_damage: float


# a per-item property's setting -> where the typed scene keeps its values
PER_ITEM_FIELDS = {"materials.units.E": ("units", "E"), "materials.units.ft": ("units", "ft"),
                   "materials.joints.ft": ("joints", "ft"), "materials.joints.phi": ("joints", "phi")}


@dataclass(frozen=True, eq=False)
class Scene:
    name: str
    geometry: Geometry
    physics: Physics
    materials: Materials
    loading: Loading
    discretization: Discretization
    integration: Integration
    outputs: Outputs
    description: str = ""
    settings: dict = None  # the validated mapping, SI, every default filled in

    def value(self, setting):
        """The scene's value of a setting by its dotted path (SI): a
        property given per unit or per joint, its mean over them (numpy's
        pairwise sum: of equal values, the value to its last digit or
        two)."""
        if setting in PER_ITEM_FIELDS:
            part, key = PER_ITEM_FIELDS[setting]
            return float(np.mean(getattr(getattr(self.materials, part), key)))
        node = self.settings
        for key in setting.split("."):
            if not isinstance(node, dict) or key not in node:
                raise KeyError(f"the scene {self.name!r} has no setting {setting}")
            node = node[key]
        return node


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
    fill_vertical(scene, VERTICAL_DEFAULTS)
    positioned = _given(scene, "loading", "bending") & {f"{k}_{s}" for k in ("supports", "loads")
                                                         for _, s in AXES.values()}    # before the defaults fill them in
    check_finite(scene)
    errors = sorted(_Validator(SCHEMA).iter_errors(scene), key=lambda e: list(e.absolute_path))
    if errors:
        e = errors[0]
        raise InputError(".".join(str(p) for p in e.absolute_path) or "scene", e.message)
    check_plausible(scene, SCHEMA, written)
    g, phys, num = _geometry(scene["geometry"]), _physics(scene["physics"]), _discretization(scene["numerics"])
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
    check_size(g, phys, num, loading, _default_discretization())   # before anything that takes time in proportion to the model's size
    if phys.model.plastic and (reason := g.crack_band_error(num.cells[0])):
        raise InputError("numerics.cells.0", f"{reason} (the default cells are the potential-crack units'; "
                                             "elasto-plastic units come within 2 % on 15x7x5: docs/accuracy.md)")
    check_loading(g, loading)
    return Scene(name=scene["name"], description=scene.get("description", ""), geometry=g, physics=phys,
                 materials=_materials(scene["materials"], g), loading=loading, discretization=num,
                 integration=Integration(damping=scene["numerics"]["damping"], safety=scene["numerics"]["safety"]),
                 outputs=Outputs(**scene["outputs"]), settings=scene)


def _given(scene, *path):
    """The keys a scene gives itself at a path of sections (none if absent)."""
    node = scene
    for key in path:
        node = node.get(key) if isinstance(node, dict) else None
    return set(node) if isinstance(node, dict) else set()


def build_scene(source, overrides=(), settings=None, label=None):
    """The one way to a typed scene: ``source``, a scene file's path or a
    scene mapping (copied, not changed), then its ``overrides`` as the
    command line writes them ('path.to.key=value', values parsed as YAML),
    then ``settings`` (dotted path -> value: a study's rules, a sample's
    settings, a swept level), validated.  ``label`` is appended to the
    scene's name ('willis:nonspatial:s3').  InputError names the first
    offending field as the scene or the command line writes it."""
    raw = copy.deepcopy(source) if isinstance(source, dict) else read_scene(source)
    apply_overrides(raw, overrides)
    for key, value in (settings or {}).items():
        set_value(raw, key, copy.deepcopy(value))
    if label is not None:
        raw["name"] = f"{raw.get('name', 'scene')}:{label}"
    return validate_scene(raw)


# the scene setting of the vertical precompression (the design rules' sigma_v)
PRECOMPRESSION = "loading.precompression.pressure"


def setting_unit(setting):
    """The SI unit of a scene's numeric setting ('' for a ratio); None if
    the dotted path is not one."""
    sub = schema_at(SCHEMA, setting)
    return None if sub is None else sub.get("unit", "")


def _geometry(g):
    u = g["unit"]
    return Geometry(unit_length=u["length"], unit_height=u["height"], unit_width=u["width"],
                    joint_thickness=g["joint_thickness"], courses=g["courses"], units_per_course=g["units_per_course"],
                    bond_offset=g["bond_offset"], ends=g["ends"])


def _physics(p):
    return Physics(blocks=p["blocks"], joints=p["joints"], gravity=p["gravity"], large=p["displacements"] == "large")


def _loading(lo, g, given=()):
    test = lo["test"]
    b = lo["bending"]
    direction = b["direction"]
    _, suffix = AXES[direction]
    supports, loads = placed(b, g, given, direction) if test == "bending" else (tuple(b.get(f"supports_{suffix}", ())),
                                                                                 tuple(b.get(f"loads_{suffix}", ())))
    key, section = section_of(b, g, direction)
    drive = {k: lo[test][k] for k in ("rate", "ramp_steps", "max_displacement", "load_drop", "max_steps")}
    if (past := lo[test].get("past_peak")) is not None:
        drive["past_peak"] = (past["drop"], past["after"], past["at_most"])
    return Loading(test=test, precompression=Precompression(**lo["precompression"]), drive=Drive(**drive),
                   bending=Bending(supports=supports, loads=loads, section=section,
                                   strip_width=b["strip_width"],
                                   strip_stiffness_ratio=b["strip_stiffness_ratio"], strips_turn=b["strips_turn"],
                                   strip_friction=b["strip_friction"], section_as_built=key not in b,
                                   spans_in_units="shear_span_units" in b, direction=direction))


KINDS = ("head", "bed", "crack", "strips")


def _default_discretization():
    return _discretization(copy.deepcopy({k: v["default"] for k, v in
                                          SCHEMA["properties"]["numerics"]["properties"].items()}))


def _discretization(n):
    raw = n["subcontact_refine"]
    per_kind = {k: raw.get(k, 1) for k in KINDS} if isinstance(raw, dict) else dict.fromkeys(KINDS, raw)
    refine = Refine(**{k: _axes(v) for k, v in per_kind.items()})
    return Discretization(elastic_element=n["elastic_element"], cells=tuple(n["cells"]), refine=refine,
                          refine_label=refine_label(raw), rule=n["subcontact_rule"], record_every=n["record_every"])


def _axes(refine):
    """A refinement as one integer per global axis (the schema has checked
    it: one integer >= 1, or three)."""
    return (int(refine),) * 3 if isinstance(refine, int) else tuple(int(r) for r in refine)


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
    for key, rule, part in (("Gf", "Gf_rule", mu), ("GI", "GI_per_ft", mj)):
        if key not in part and rule not in part:
            section = "units" if part is mu else "joints"
            raise InputError(f"materials.{section}.{key}", f"is required (or materials.{section}.{rule}, the rule "
                                                           "that gives it)")
    per_u, per_j = m.get("per_unit", {}), m.get("per_joint", {})
    n_units, n_joints = g.n_units, len(g.joints)
    rule = mu.get("Gf_rule")
    units = unit_fields(E=_field(mu, per_u, "E", n_units, "unit"), ft=_field(mu, per_u, "ft", n_units, "unit"),
                        nu=mu["nu"], c_ratio=mu["c_ratio"], phi=mu["phi"], psi=mu["psi"], Gf=mu.get("Gf"),
                        density=mu["density"],
                        crack_kn_ratio=mu["crack_kn_ratio"],
                        gf_rule=(rule["coefficient"], rule["exponent"]) if rule else None)
    joints = joint_fields(ft=_field(mj, per_j, "ft", n_joints, "joint"), phi=_field(mj, per_j, "phi", n_joints, "joint"),
                          c_ratio=mj["c_ratio"], GI=mj.get("GI"), GII_ratio=mj["GII_ratio"], Em_ratio=mj["Em_ratio"],
                          ks_ratio=mj["ks_ratio"], gi_per_ft=mj.get("GI_per_ft"),
                          residual_friction_ratio=mj["residual_friction_ratio"])
    return Materials(units=units, joints=joints)
