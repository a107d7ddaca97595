"""Renders the demo's frames with Blender's Workbench through the `bpy` wheel, headless.

The scene is built once from arrays (the body and the garment as two meshes, a camera, a
studio light); for each frame the two meshes' vertices are replaced with `foreach_set` (one
copy each) and a still is rendered. The arrays are Y-up (glTF, garment files) and turned to
Blender's Z-up here: (x, y, z) -> (x, -z, y). A contact sheet (a grid of frames, labelled by
nothing but their order) is composed from the written PNGs with numpy, and an animated GIF of
the frames with Pillow (`animation`).
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np

SKIN = (0.80, 0.62, 0.52)
BACKGROUND = (0.93, 0.93, 0.95)


def ensure(module: str, requirement: str, what: str) -> None:
    """Imports `module`, installing `requirement` into this interpreter first if it is missing
    (the bootstrap installs it; a plain `pip install tailor` environment may not have it)."""
    import importlib

    try:
        importlib.import_module(module)
        return
    except ImportError:
        pass
    print(f'demo: {module} is missing: installing "{requirement}" ({what})', flush=True)
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", requirement], check=True)
    importlib.invalidate_caches()
    importlib.import_module(module)


def ensure_bpy() -> None:
    ensure("bpy", "bpy==4.5.*", "Blender as a Python module, ~370 MB")


def z_up(p: np.ndarray) -> np.ndarray:
    p = np.asarray(p, np.float32)
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


class Renderer:
    def __init__(self, body_tris: np.ndarray, cloth_tris: np.ndarray, cloth_colour, size=(480, 360),
                 target=(0.0, 0.0, 1.05), distance=3.6, elevation_deg=8.0, azimuth_deg=-28.0):
        ensure_bpy()
        import bpy

        bpy.ops.wm.read_factory_settings(use_empty=True)
        self.bpy = bpy
        scene = bpy.context.scene
        scene.render.engine = "BLENDER_WORKBENCH"
        scene.render.resolution_x, scene.render.resolution_y = size
        scene.render.resolution_percentage = 100
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGB"
        scene.render.film_transparent = False
        scene.view_settings.view_transform = "Standard"
        shading = scene.display.shading
        shading.light = "STUDIO"
        shading.color_type = "MATERIAL"
        shading.show_shadows = True
        shading.shadow_intensity = 0.35
        shading.show_cavity = True
        shading.cavity_type = "WORLD"
        shading.show_specular_highlight = False
        scene.display.render_aa = "5"
        world = bpy.data.worlds.new("Demo")
        world.color = BACKGROUND
        scene.world = world
        self.body = self._mesh("Body", body_tris, SKIN)
        self.cloth = self._mesh("Garment", cloth_tris, cloth_colour)
        cam_data = bpy.data.cameras.new("Camera")
        cam_data.lens = 50.0
        cam = bpy.data.objects.new("Camera", cam_data)
        scene.collection.objects.link(cam)
        az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
        # Blender: the character faces -Y; azimuth 0 looks at its front.
        offset = np.array([math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)]) * distance
        from mathutils import Vector

        cam.location = Vector(np.asarray(target) + offset)
        cam.rotation_euler = (Vector(target) - cam.location).to_track_quat("-Z", "Y").to_euler()
        scene.camera = cam
        self.scene = scene

    def _mesh(self, name: str, tris: np.ndarray, colour):
        bpy = self.bpy
        tris = np.asarray(tris, np.int32)
        n = int(tris.max()) + 1
        me = bpy.data.meshes.new(name)
        me.vertices.add(n)
        me.loops.add(tris.size)
        me.loops.foreach_set("vertex_index", tris.ravel())
        me.polygons.add(len(tris))
        me.polygons.foreach_set("loop_start", np.arange(0, tris.size, 3, dtype=np.int32))
        me.polygons.foreach_set("use_smooth", np.ones(len(tris), bool))
        me.update()
        mat = bpy.data.materials.new(name)
        mat.diffuse_color = (*colour, 1.0)
        me.materials.append(mat)
        obj = bpy.data.objects.new(name, me)
        self_scene = bpy.context.scene
        self_scene.collection.objects.link(obj)
        return obj

    def set(self, body: np.ndarray, cloth: np.ndarray | None) -> None:
        for obj, p in ((self.body, body), (self.cloth, cloth)):
            obj.hide_render = p is None
            if p is not None:
                obj.data.vertices.foreach_set("co", z_up(p).ravel())
                obj.data.update()

    def render(self, path: Path) -> None:
        self.scene.render.filepath = str(path)
        self.bpy.ops.render.render(write_still=True)

    def read_png(self, path: Path) -> np.ndarray:
        """(h, w, 3) float32 pixels of a PNG, top row first."""
        img = self.bpy.data.images.load(str(path), check_existing=False)
        w, h = img.size
        px = np.empty(w * h * 4, np.float32)
        img.pixels.foreach_get(px)
        self.bpy.data.images.remove(img)
        return px.reshape(h, w, 4)[::-1, :, :3]

    def write_png(self, path: Path, pixels: np.ndarray) -> None:
        h, w = pixels.shape[:2]
        img = self.bpy.data.images.new("sheet", w, h, alpha=False)
        rgba = np.ones((h, w, 4), np.float32)
        rgba[:, :, :3] = pixels[::-1]
        img.pixels.foreach_set(rgba.ravel())
        img.filepath_raw = str(path)
        img.file_format = "PNG"
        img.save()
        self.bpy.data.images.remove(img)


def contact_sheet(frames: list[np.ndarray], columns: int, gap: int = 4) -> np.ndarray:
    """A grid of equally sized frames on the background colour, left to right, top to bottom."""
    h, w = frames[0].shape[:2]
    rows = -(-len(frames) // columns)
    sheet = np.empty((rows * h + (rows + 1) * gap, columns * w + (columns + 1) * gap, 3), np.float32)
    sheet[:] = 1.0
    for i, f in enumerate(frames):
        r, c = divmod(i, columns)
        y, x = gap + r * (h + gap), gap + c * (w + gap)
        sheet[y:y + h, x:x + w] = f
    return sheet


def animation(frames: list[Path], path: Path, fps: float, width: int | None = None) -> dict:
    """An animated GIF of the PNG `frames` at `fps`, looping, scaled to `width` pixels (None: as
    rendered). GIF because every browser, viewer and Markdown renderer plays it; each frame gets
    its own 256-colour palette (the renders are smooth shading on a flat background) and Pillow
    stores only the part of each frame that changed."""
    ensure("PIL", "pillow>=10", "image library, ~4 MB")
    from PIL import Image

    images = []
    for f in frames:
        with Image.open(f) as im:
            im = im.convert("RGB")
            if width and im.width != width:
                im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
            images.append(im)
    duration = max(20, round(1000.0 / fps / 10) * 10)  # GIF delays are in 1/100 s
    images[0].save(path, save_all=True, append_images=images[1:], duration=duration, loop=0, optimize=True,
                   disposal=1)
    return {"file": path.name, "frames": len(images), "size": f"{images[0].width}x{images[0].height}",
            "ms_per_frame": duration, "bytes": path.stat().st_size}
