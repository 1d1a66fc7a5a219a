"""Shaded pictures of the posed assembly without a GPU: a still (PNG) and the stroke (GIF).

The same inputs as the ``.glb`` (:mod:`cad.export.gltf`): part instances, body poses over
the stroke ``{body: (N, 4, 4)}`` (mm) and the parts' meshes. Each frame is an
orthographic view from ``VIEW_AZIM_DEG`` / ``VIEW_ELEV_DEG`` (world R0, z up): triangles
facing away are culled, the others shaded flat by a headlight (Lambert, ``AMBIENT``
floor) and drawn with a per-pixel depth test (:mod:`cad.report.raster`, numpy z-buffer)
at ``SUPERSAMPLE`` times the size, then averaged down (anti-aliasing).
The frame's extent is the union over every pose, so the view does not jump. Bodies that
do not move over the stroke (the stand) are drawn once into the depth buffer that every
GIF frame starts from.

GIF frames go forward over the stroke and back (a loop), written with Pillow.
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from cad.io.atomic import write_bytes_atomic
from cad.report import raster
from cad.report.cutaway import cut_quarter

VIEW_AZIM_DEG = -55.0
VIEW_ELEV_DEG = 35.0
AMBIENT = 0.35
#: Frames of the GIF over one way of the stroke, and the time per frame (ms).
GIF_POSES = 12
GIF_FRAME_MS = 90
#: Frames are drawn at this multiple of their size and reduced (anti-aliasing).
SUPERSAMPLE = 2
#: Colour of the thin lines drawn over a picture (exploded views' axes).
LINE_RGB = (90, 90, 90)


def view_basis(azim_deg: float = VIEW_AZIM_DEG, elev_deg: float = VIEW_ELEV_DEG) -> np.ndarray:
    """3x3 rows: screen right, screen up, towards the viewer (world R0 coordinates)."""
    a, e = math.radians(azim_deg), math.radians(elev_deg)
    toward = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross([0.0, 0.0, 1.0], toward)
    right /= np.linalg.norm(right)
    up = np.cross(toward, right)
    return np.array([right, up, toward])


def _view_triangles(instances, tf_world_body, meshes, colors, basis, i: int, cutaway=None):
    """Triangles at pose ``i`` in view coordinates (T, 3, 3) mm (x right, y up, z toward
    the viewer; ``basis`` from :func:`view_basis`) and their RGB (T, 3). ``cutaway``:
    ``(centre (3,) mm world, instance names)``: those instances lose the quarter facing
    the viewer (:func:`cad.report.cutaway.cut_quarter`)."""
    tris, rgb = [np.empty((0, 3, 3))], [np.empty((0, 3))]
    for inst in instances:
        v, f = meshes[inst.kind.name]
        T = tf_world_body[inst.body][i] @ inst.tf_body_part
        t = (np.asarray(v) @ T[:3, :3].T + T[:3, 3])[np.asarray(f)]  # world
        if cutaway is not None and inst.name in cutaway[1]:
            t, _ = cut_quarter(t, cutaway[0], basis[2])
        tris.append(t @ basis.T)
        rgb.append(np.broadcast_to(np.asarray(colors[inst.name], dtype=float), (len(t), 3)))
    return np.concatenate(tris), np.concatenate(rgb)


def _shaded(s, rgb):
    """The triangles facing the viewer (view coordinates, (T, 3, 3)) and their RGB shaded
    by a headlight: ``AMBIENT + (1 - AMBIENT) cos(normal, toward the viewer)``."""
    u, v = s[:, 1] - s[:, 0], s[:, 2] - s[:, 0]
    nz = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]  # normal . toward the viewer (x area)
    keep = nz > 0
    s, u, v, nz, rgb = s[keep], u[keep], v[keep], nz[keep], rgb[keep]
    nx = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    ny = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    shade = AMBIENT + (1.0 - AMBIENT) * nz / np.sqrt(nx * nx + ny * ny + nz * nz)
    return s, np.clip(rgb * shade[:, None], 0.0, 1.0)


def _extent(instances, tf_world_body, meshes, basis, poses) -> tuple[np.ndarray, np.ndarray]:
    """View-coordinate box (lo (3,), hi (3,)) of the instances over every pose."""
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for inst in instances:
        v = np.asarray(meshes[inst.kind.name][0])
        for i in poses:
            T = tf_world_body[inst.body][i] @ inst.tf_body_part
            p = v @ (basis @ T[:3, :3]).T + basis @ T[:3, 3]
            lo, hi = np.minimum(lo, p.min(axis=0)), np.maximum(hi, p.max(axis=0))
    return lo, hi


def _static_bodies(tf_world_body, poses) -> set[str]:
    """Bodies whose transform is the same at every pose of ``poses``."""
    return {
        b
        for b, T in tf_world_body.items()
        if all(np.array_equal(T[poses[0]], T[i]) for i in poses[1:])
    }


def render_images(
    instances,
    tf_world_body,
    meshes,
    colors,
    poses,
    *,
    size_px=(640, 480),
    title: str = "",
    supersample: int = SUPERSAMPLE,
    lines=(),
    cutaway=None,
) -> list:
    """RGB pictures (``PIL.Image``, ``size_px``) of the assembly at each pose index in ``poses``
    (module docstring); only listed parts are drawn.

    colors : ``{instance name: (r, g, b)}`` in 0..1 (:func:`cad.export.gltf.instance_rgb`).
    lines : world segments (L, 2, 3) mm drawn thin over every picture (the axes of an
        exploded view, :mod:`cad.report.step_views`); they do not widen the frame.
    cutaway : ``(centre (3,) mm world, instance names)`` or None: those instances are
        drawn without the quarter facing the viewer (:mod:`cad.report.cutaway`).
    """
    from PIL import Image, ImageDraw, ImageFont


    basis = view_basis()
    shown = [inst for inst in instances if inst.kind.listed]
    W, H = size_px[0] * supersample, size_px[1] * supersample
    lo, hi, to_px = _frame(shown, tf_world_body, meshes, basis, poses, (W, H))
    z_range = max(hi[2] - lo[2], 1e-9)

    def draw(insts, i, keys, box, id_offset=0):
        """Rasterize into ``keys``, the (rows, cols) = ``box`` part of the picture."""
        s, rgb = _shaded(*_view_triangles(insts, tf_world_body, meshes, colors, basis, i,
                                          cutaway))
        px = np.stack(to_px(s), axis=-1) - [box[1].start, box[0].start]
        width = box[1].stop - box[1].start
        raster.rasterize(px, (s[..., 2] - lo[2]) / z_range, keys, width, id_offset)
        rgba = np.full((len(rgb) + 1, 4), 255, np.uint8)  # white first: the background
        rgba[1:, :3] = rgb * 255 + 0.5
        return rgba.view(np.uint32)[:, 0]  # one 32-bit word per colour: a fast lookup

    def picture(keys, palette, box):
        """The RGB picture of ``keys`` (``box`` of the supersampled frame), reduced."""
        h, w = box[0].stop - box[0].start, box[1].stop - box[1].start
        rgbx = palette[raster.triangle_ids(keys)]
        img = Image.frombuffer("RGBX", (w, h), rgbx, "raw", "RGBX", 0, 1)
        return img.reduce(supersample).convert("RGB")  # box filter: the mean of each block

    # the stand: drawn once; each frame redraws only the box its moving parts sweep
    still = _static_bodies(tf_world_body, poses)
    moving = [x for x in shown if x.body not in still]
    frame = (slice(0, H), slice(0, W))
    static_keys = raster.empty_keys(H, W)
    static_rgb = draw([x for x in shown if x.body in still], poses[0], static_keys, frame)
    static_img = picture(static_keys, static_rgb, frame)
    n = supersample
    box = _moving_box(_extent(moving, tf_world_body, meshes, basis, poses), to_px, n, (W, H))
    box_keys = static_keys.reshape(H, W)[box]
    font = ImageFont.load_default(size=max(12, size_px[1] // 30)) if title else None
    out = []
    for i in poses:
        img = static_img.copy()
        if moving:
            keys = box_keys.copy().reshape(-1)
            rgb = draw(moving, i, keys, box, len(static_rgb) - 1)
            palette = np.concatenate([static_rgb, rgb[1:]])
            img.paste(picture(keys, palette, box), (box[1].start // n, box[0].start // n))
        if len(lines):
            _draw_lines(ImageDraw.Draw(img), np.asarray(lines, float) @ basis.T, to_px, supersample)
        if title:
            ImageDraw.Draw(img).text((8, 6), title, fill=(64, 64, 64), font=font)
        out.append(img)
    return out


def _moving_box(extent, to_px, n: int, size_px) -> tuple[slice, slice]:
    """Rows and columns of the picture (``size_px = (W, H)``, supersampled by ``n``) that the
    view box ``extent = (lo, hi)`` covers, in whole supersampling blocks (reduce cuts the
    same); the whole picture when the box is empty."""
    W, H = size_px
    m_lo, m_hi = extent
    if not (np.isfinite(m_lo).all() and np.isfinite(m_hi).all()):
        return slice(0, H), slice(0, W)
    (x0, x1), (y1, y0) = to_px(np.array([m_lo, m_hi]))  # y down: hi is the top
    c0, c1 = max(int(x0 // n) * n - n, 0), min(int(x1 // n) * n + 2 * n, W)
    r0, r1 = max(int(y0 // n) * n - n, 0), min(int(y1 // n) * n + 2 * n, H)
    return slice(r0, r1), slice(c0, c1)


def _frame(shown, tf_world_body, meshes, basis, poses, size_px):
    """The picture's frame: the view box ``(lo, hi)`` of ``shown`` over ``poses`` and
    ``to_px(view points (..., 3)) -> (x, y)`` pixels of a ``size_px = (W, H)`` picture
    (the box fills it with a 4 % margin, centred)."""
    lo, hi = _extent(shown, tf_world_body, meshes, basis, poses)
    pad = 0.04 * (hi[:2] - lo[:2]).max()
    W, H = size_px
    scale = min(W / (hi[0] - lo[0] + 2 * pad), H / (hi[1] - lo[1] + 2 * pad))
    centre = 0.5 * (lo + hi)

    def to_px(s):
        return W / 2 + (s[..., 0] - centre[0]) * scale, H / 2 - (s[..., 1] - centre[1]) * scale

    return lo, hi, to_px


def _draw_lines(draw, segs_view, to_px, supersample: int) -> None:
    """Thin lines (``LINE_RGB``, 1 px, over the parts) of segments (L, 2, 3) in view
    coordinates, into a picture reduced by ``supersample``."""
    x, y = to_px(segs_view)
    for (x0, x1), (y0, y1) in zip(x / supersample, y / supersample, strict=True):
        draw.line([(x0, y0), (x1, y1)], fill=LINE_RGB, width=1)


def picture_px(points_mm, instances, tf_world_body, meshes, poses, size_px=(640, 480)):
    """Pixel coordinates (..., 2) (x right, y down) of world points (..., 3) mm in the
    picture :func:`render_images` draws of the same inputs."""
    basis = view_basis()
    shown = [inst for inst in instances if inst.kind.listed]
    _, _, to_px = _frame(shown, tf_world_body, meshes, basis, poses, size_px)
    return np.stack(to_px(np.asarray(points_mm, float) @ basis.T), axis=-1)


def png_bytes(img) -> bytes:
    """PNG of a ``PIL.Image``."""
    buf = io.BytesIO()
    img.save(buf, format="PNG")
    return buf.getvalue()


def gif_bytes(imgs: list, frame_ms: int = GIF_FRAME_MS) -> bytes:
    """An endlessly looping GIF of the RGB frames (``PIL.Image``) forward then back
    (Pillow; one adaptive palette from the middle frame, so colours do not flicker)."""
    from PIL import Image

    order = list(range(len(imgs))) + list(range(len(imgs) - 2, 0, -1))
    first = imgs[order[len(order) // 2]].quantize(colors=128, method=Image.Quantize.MEDIANCUT)
    quantized = [im.quantize(palette=first, dither=Image.Dither.NONE) for im in imgs]
    pal = [quantized[k] for k in order]
    buf = io.BytesIO()
    pal[0].save(buf, format="GIF", save_all=True, append_images=pal[1:], duration=frame_ms, loop=0)
    return buf.getvalue()


def cutaway_of(names, instances, tf_pose, meshes):
    """``(centre (3,) mm, names)`` for :func:`render_images`: the centre of the named
    instances' world box at ``tf_pose`` (``{body: (4, 4)}``); None when ``names`` is empty."""
    chosen = [i for i in instances if i.name in set(names) and i.kind.name in meshes]
    if not chosen:
        return None
    pts = []
    for inst in chosen:
        T = np.asarray(tf_pose[inst.body], dtype=float).reshape(4, 4) @ inst.tf_body_part
        pts.append(np.asarray(meshes[inst.kind.name][0]) @ T[:3, :3].T + T[:3, 3])
    p = np.concatenate(pts)
    return 0.5 * (p.min(axis=0) + p.max(axis=0)), frozenset(i.name for i in chosen)


def write_stroke_pictures(
    instances, tf_pose, stroke, meshes, colors, out_dir: Path, *, title: str, cutaway=()
) -> list[str]:
    """``animation.gif`` (``stroke``: ``{body: (N, 4, 4)}``) and ``render.png`` (the still
    at ``tf_pose``: ``{body: (4, 4)}``), mm. ``cutaway``: names of the instances drawn
    cut away (:func:`cutaway_of`; a housing that would hide what moves inside)."""
    n = len(next(iter(stroke.values())))
    poses = list(range(n))
    if n > GIF_POSES:
        poses = sorted({int(round(x)) for x in np.linspace(0, n - 1, GIF_POSES)})
    cut = cutaway_of(cutaway, instances, tf_pose, meshes)
    frames = render_images(instances, stroke, meshes, colors, poses, title=title, cutaway=cut)
    write_bytes_atomic(Path(out_dir) / "animation.gif", gif_bytes(frames))
    static = {b: np.asarray(T, dtype=float).reshape(1, 4, 4) for b, T in tf_pose.items()}
    (still,) = render_images(
        instances, static, meshes, colors, [0], size_px=(960, 720), title=title, cutaway=cut
    )
    write_bytes_atomic(Path(out_dir) / "render.png", png_bytes(still))
    return ["animation.gif", "render.png"]
