"""Shaded pictures of the posed assembly without a GPU: a still (PNG) and the stroke (GIF).

The same inputs as the ``.glb`` (:mod:`cad.export.gltf`): part instances, body poses over
the stroke ``{body: (N, 4, 4)}`` (mm) and the parts' meshes. Each frame is an
orthographic view from ``VIEW_AZIM_DEG`` / ``VIEW_ELEV_DEG`` (world R0, z up): triangles
facing away are culled, large ones split (better depth order), the others shaded by a headlight (Lambert, ``AMBIENT`` floor)
and filled back to front (painter's algorithm) with Pillow.
The frame's extent is the union over every pose, so the view does not jump.

GIF frames go forward over the stroke and back (a loop), written with Pillow.
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

VIEW_AZIM_DEG = -55.0
VIEW_ELEV_DEG = 35.0
AMBIENT = 0.35
#: Frames of the GIF over one way of the stroke, and the time per frame (ms).
GIF_POSES = 12
GIF_FRAME_MS = 90
#: Frames are drawn at this multiple of their size and reduced (anti-aliasing).
SUPERSAMPLE = 2
#: Triangles larger than (this fraction of the picture)² are split (at most SUBDIVIDE_LEVELS times).
SUBDIVIDE_FRACTION = 0.04
SUBDIVIDE_LEVELS = 4


def view_basis(azim_deg: float = VIEW_AZIM_DEG, elev_deg: float = VIEW_ELEV_DEG) -> np.ndarray:
    """3x3 rows: screen right, screen up, towards the viewer (world R0 coordinates)."""
    a, e = math.radians(azim_deg), math.radians(elev_deg)
    toward = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross([0.0, 0.0, 1.0], toward)
    right /= np.linalg.norm(right)
    up = np.cross(toward, right)
    return np.array([right, up, toward])


def _scene_triangles(instances, tf_world_body, meshes, colors, i: int):
    """World triangles (T, 3, 3) mm and their RGB (T, 3) at pose ``i``."""
    tris, rgb = [], []
    for inst in instances:
        k = inst.kind
        if not k.listed:
            continue
        v, f = meshes[k.name]
        T = tf_world_body[inst.body][i] @ inst.tf_body_part
        w = np.asarray(v) @ T[:3, :3].T + T[:3, 3]
        tris.append(w[np.asarray(f)])
        rgb.append(np.broadcast_to(np.asarray(colors[inst.name], dtype=float), (len(f), 3)))
    return np.concatenate(tris), np.concatenate(rgb)


def _subdivide(tri: np.ndarray, rgb: np.ndarray, max_size: float):
    """Split triangles of area above ``max_size``² into four (midpoints), at most
    SUBDIVIDE_LEVELS times: a large face sorted by its centre would otherwise hide or show
    what it should not (a base plate over its post)."""
    for _ in range(SUBDIVIDE_LEVELS):
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        big = area > max_size**2
        if not big.any():
            break
        a, b, c = tri[big, 0], tri[big, 1], tri[big, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        new = np.concatenate(
            [np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]
        )
        tri = np.concatenate([tri[~big], new])
        rgb = np.concatenate([rgb[~big], np.tile(rgb[big], (4, 1))])
    return tri, rgb


def _shaded(tri_w, rgb, basis):
    """Visible triangles in screen coordinates (T, 3, 2), back to front, with shaded RGB."""
    s = tri_w @ basis.T  # screen coordinates (x right, y up, z toward the viewer)
    n = np.cross(s[:, 1] - s[:, 0], s[:, 2] - s[:, 0])
    norm = np.linalg.norm(n, axis=1)
    keep = (n[:, 2] > 0) & (norm > 0)
    s, n, norm, rgb = s[keep], n[keep], norm[keep], rgb[keep]
    shade = AMBIENT + (1.0 - AMBIENT) * (n[:, 2] / norm)
    order = np.argsort(s[:, :, 2].mean(axis=1), kind="stable")
    return s[order][:, :, :2], np.clip(rgb[order] * shade[order, None], 0.0, 1.0)


def _extent(instances, tf_world_body, meshes, basis, poses) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for inst in instances:
        if not inst.kind.listed:
            continue
        v = np.asarray(meshes[inst.kind.name][0])
        for i in poses:
            T = tf_world_body[inst.body][i] @ inst.tf_body_part
            p = (v @ T[:3, :3].T + T[:3, 3]) @ basis[:2].T
            lo, hi = np.minimum(lo, p.min(axis=0)), np.maximum(hi, p.max(axis=0))
    pad = 0.04 * (hi - lo).max()
    return lo - pad, hi + pad


def render_frames(
    instances,
    tf_world_body,
    meshes,
    colors,
    poses,
    *,
    size_px=(640, 480),
    title: str = "",
    supersample: int = SUPERSAMPLE,
) -> list[bytes]:
    """PNG bytes of the assembly at each pose index in ``poses`` (module docstring).

    colors : ``{instance name: (r, g, b)}`` in 0..1 (:func:`cad.export.gltf.instance_rgb`).
    Triangles are filled with Pillow at ``supersample`` times the size, then reduced
    (Lanczos) for smooth edges.
    """
    from PIL import Image, ImageDraw, ImageFont

    basis = view_basis()
    lo, hi = _extent(instances, tf_world_body, meshes, basis, poses)
    W, H = size_px[0] * supersample, size_px[1] * supersample
    scale = min(W / (hi[0] - lo[0]), H / (hi[1] - lo[1]))
    centre = 0.5 * (lo + hi)
    out = []
    for i in poses:
        tri, rgb = _scene_triangles(instances, tf_world_body, meshes, colors, i)
        tri, rgb = _shaded(*_subdivide(tri, rgb, SUBDIVIDE_FRACTION * (hi - lo).max()), basis)
        px = np.empty_like(tri)
        px[..., 0] = W / 2 + (tri[..., 0] - centre[0]) * scale
        px[..., 1] = H / 2 - (tri[..., 1] - centre[1]) * scale
        img = Image.new("RGB", (W, H), "white")
        draw = ImageDraw.Draw(img)
        col = (rgb * 255 + 0.5).astype(np.uint8)
        for p, c in zip(px.tolist(), map(tuple, col.tolist()), strict=True):
            draw.polygon([tuple(q) for q in p], fill=c, outline=c)
        img = img.resize(size_px, Image.Resampling.LANCZOS)
        if title:
            font = ImageFont.load_default(size=max(12, size_px[1] // 30))
            ImageDraw.Draw(img).text((8, 6), title, fill=(64, 64, 64), font=font)
        buf = io.BytesIO()
        img.save(buf, format="PNG", optimize=False)
        out.append(buf.getvalue())
    return out


def gif_bytes(frames_png: list[bytes], frame_ms: int = GIF_FRAME_MS) -> bytes:
    """An endlessly looping GIF of the frames forward then back (Pillow; one adaptive
    palette from the middle frame, so colours do not flicker)."""
    from PIL import Image

    imgs = [Image.open(io.BytesIO(b)).convert("RGB") for b in frames_png]
    seq = imgs + imgs[-2:0:-1]
    first = seq[len(seq) // 2].quantize(colors=128, method=Image.Quantize.MEDIANCUT)
    pal = [im.quantize(palette=first, dither=Image.Dither.NONE) for im in seq]
    buf = io.BytesIO()
    pal[0].save(buf, format="GIF", save_all=True, append_images=pal[1:], duration=frame_ms, loop=0)
    return buf.getvalue()


def write_stroke_pictures(
    instances, tf_pose, stroke, meshes, colors, out_dir: Path, *, title: str
) -> list[str]:
    """``animation.gif`` (``stroke``: ``{body: (N, 4, 4)}``) and ``render.png`` (the still
    at ``tf_pose``: ``{body: (4, 4)}``), mm."""
    from cad.io.atomic import write_bytes_atomic

    n = len(next(iter(stroke.values())))
    poses = list(range(n))
    if n > GIF_POSES:
        poses = sorted({int(round(x)) for x in np.linspace(0, n - 1, GIF_POSES)})
    frames = render_frames(instances, stroke, meshes, colors, poses, title=title)
    write_bytes_atomic(Path(out_dir) / "animation.gif", gif_bytes(frames))
    static = {b: np.asarray(T, dtype=float).reshape(1, 4, 4) for b, T in tf_pose.items()}
    still = render_frames(instances, static, meshes, colors, [0], size_px=(960, 720), title=title)[
        0
    ]
    write_bytes_atomic(Path(out_dir) / "render.png", still)
    return ["animation.gif", "render.png"]
