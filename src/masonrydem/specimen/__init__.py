"""One wallette (or another specimen) in one test: a scene read and
validated (files.py, quantities.py, scene.py and its schema), built by
the masonry rules (masonry.py, bending.py, build.py) into a solver model,
run through its test (protocol.py), classified (classify.py) and written
as one result row and curve (row.py), with its 3-D state (state.py).

``scene.build_scene`` is the one way from a scene file, its overrides and
a study sample's settings to a typed scene."""
