"""Simulate (issue 7): live and baked simulation of the scene's garment on its colliders.

Registered but empty until the Simulate panel lands. It builds its `tailor.Simulation` with
`scene_data.build_garment(scene).build_simulation(...)` and reads painted maps with
`paint.maps.painted_maps(obj)`; see docs/addon.md. Add `properties.py`, `operators.py` and
`ui.py` here and list their classes below (registered after the other features, so its panel
comes last in the Tailor tab).
"""

classes = ()


def register() -> None:
    pass


def unregister() -> None:
    pass
