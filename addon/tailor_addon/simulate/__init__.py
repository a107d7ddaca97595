"""Simulate (issue 7): the garment on its colliders, live and baked.

- `properties.py`: the panel's settings (`Scene.tailor_simulate`) and `Object.tailor_collider`;
- `gather.py`: scene -> arrays (settings, fabric, painted maps, colliders evaluated every frame);
- `job.py`: a bake (`tailor.bake.Bake` driven frame by frame, PC2 caches, Mesh Cache playback);
- `live.py`, `draw.py`: Live mode's main-thread half and its overlay (the worker thread is
  `core/simulate_live.py`);
- `operators.py`, `ui.py`: the operators and the panel.

The simulation itself is built by the bpy-free `core/simulate.py`.
"""

from . import draw, live, operators, properties, ui

classes = properties.classes + operators.classes + ui.classes


def register() -> None:
    properties.register()


def unregister() -> None:
    live.stop_all()
    draw.remove()
    properties.unregister()
