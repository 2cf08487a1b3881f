"""The scene: a specimen as plain data, below everything that computes.

A scene file (YAML; the schema with each setting's default and plausible
range: schema.yaml) is read (``read_scene``), its quantities converted to
SI (``to_si``; units as the file writes them), checked, and turned into a
typed, frozen ``Scene`` (``build_scene``) of numbers, tuples and names:
block models and joint laws are named by strings.  Nothing here imports
the solver or its compiler: reading and checking any scene or study file
loads neither (specimen.build maps a Scene to the solver's types).

Modules: files (reading YAML and --set overrides), quantities (units and
plausibility), masonry (the geometry of running bond and the rules that
derive the joints' and units' fields), bending (where the supports and
loads go), size (a model's size from its numbers alone), typed (the
typed Scene and its validation).
"""
from .files import MAX_BYTES, apply_overrides, read_scene, read_yaml, set_value
from .masonry import (Geometry, JointFields, UnitFields, crack_stiffness, flexural_strength, joint_kn,
                      joint_stiffness)
from .quantities import column, is_plain, meant, shown, to_shown, to_si
from .size import model_size
from .typed import (BLOCK_MODELS, PRECOMPRESSION, SCHEMA, BlockModel, Scene, build_scene, refine_label,
                    setting_unit, validate_scene)

__all__ = ["BLOCK_MODELS", "MAX_BYTES", "PRECOMPRESSION", "SCHEMA", "BlockModel", "Geometry", "JointFields",
           "Scene", "UnitFields", "apply_overrides", "build_scene", "column", "crack_stiffness",
           "flexural_strength", "is_plain", "joint_kn", "joint_stiffness", "meant", "model_size", "read_scene",
           "read_yaml", "refine_label", "set_value", "setting_unit", "shown", "to_shown", "to_si",
           "validate_scene"]
