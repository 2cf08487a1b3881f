"""The discrete element solver: deformable or rigid blocks joined by
zero-thickness joints, integrated explicitly (docs/formulation.md).

- model.py: ``Model``, blocks, joints, supports and loads, and ``build``;
- laws.py: the block materials and joint laws (each a small compiled
  function chosen once);
- mesh.py, elements.py, blocks.py, contacts.py, assembly.py: the meshes,
  cells, faces, sub-contacts and the assembled arrays;
- solver.py: ``init`` and ``advance`` over a state (``Numerics``:
  how to integrate); stops.py: an advance loop under stop rules;
  history.py: what a run records; stability.py: masses and steps;
- kernels/: the compiled step.

Nothing here knows of masonry, a test or a study."""
