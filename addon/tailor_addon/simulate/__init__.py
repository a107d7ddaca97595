"""Simulate (issue 7): the garment on its colliders, live and baked.

- `properties.py`: the panel's settings (`Scene.tailor_simulate`) and `Object.tailor_collider`;
- `gather.py`: scene -> arrays (settings, fabric, painted maps, colliders evaluated every frame);
- `job.py`: a bake (`tailor.bake.Bake` driven frame by frame, PC2 caches, Mesh Cache playback);
- `live.py`, `draw.py`: Live mode's main-thread half and its overlay (the solver, its solves on
  native threads, is `core/simulate_live.py`);
- `fit_map_attrs.py`, `fit_map_draw.py`: the fit maps written onto the pieces, and drawn over
  them as an overlay;
- `runs.py`: the modal bake's and Live's runs (timer, progress, how each ends or is cancelled);
- `handlers.py`: runs end before a file is replaced; older files' settings carried over;
- `operators.py`, `ui.py`: the operators and the panel;
- `export_welded.py`: Export Welded Garment (the pieces merged along their seams into one mesh
  at the current frame, optionally written as OBJ or glTF);
- `export_animation.py`: Export Garment Animation (the baked garment welded, animated over the
  bake's range, written as Alembic or USD by Blender's exporters).

The simulation itself is built by the bpy-free `core/simulate.py`.
"""

from . import draw, export_animation, fit_map_draw, export_welded, handlers, live, operators, properties, runs, ui

classes = properties.classes + operators.classes + export_welded.classes + export_animation.classes + ui.classes


#: Object > Tailor menu entries (menu.EXTRA), in workflow order.
MENU = (
    ("tailor.mark_collider", "Mark Collider"),
    ("tailor.collider_proxy", "Make Collider Proxy"),
    ("tailor.live", "Simulate Live"),
    ("tailor.live_step", "Live Step"),
    ("tailor.live_stop", "Stop Live"),
    ("tailor.bake", "Bake Simulation"),
    ("tailor.bake_clear", "Free Bake"),
    ("tailor.export_welded", "Export Welded Garment"),
    ("tailor.export_animation", "Export Garment Animation"),
)


def register() -> None:
    from .. import menu

    properties.register()
    handlers.register()
    fit_map_draw.register()
    menu.EXTRA.extend(e for e in MENU if e not in menu.EXTRA)


def unregister() -> None:
    from .. import menu

    handlers.unregister()
    fit_map_draw.unregister()
    runs.abandon_all()
    live.stop_all()
    draw.remove()
    menu.EXTRA[:] = [e for e in menu.EXTRA if e not in MENU]
    properties.unregister()
