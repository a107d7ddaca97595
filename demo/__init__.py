"""The demo of ``make demo`` (``python demo/run.py`` or ``python -m demo``; see `demo.run`).

It lives in the source tree, outside the ``tailor`` package that ships in the Blender add-on:
it reads the checkout's samples (``sample_blends/``) and renders with the `bpy` wheel.
"""
