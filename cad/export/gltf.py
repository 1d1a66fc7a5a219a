"""Binary glTF 2.0 (``.glb``) of the posed assembly, with the mechanism's stroke as an animation.

Input is the build's one assembly model: part instances (``name``, ``kind`` with
``shape``/``material``/``made``, ``body``, ``tf_body_part``) and the world transforms of
every body over the stroke (``{body: (N, 4, 4)}``, mm, from the family's kinematics).

Layout of the file (glTF 2.0, written with pygltflib):

* scene 0 -> one root node named after the design -> one node per body, named
  ``body:<body>`` (translation + rotation = the body's pose at ``pose_index``) -> one
  node per part instance, named by the instance, at ``tf_body_part`` (a ``matrix``);
* one mesh per part kind (shared by its instances), named by the kind, one primitive
  (POSITION float32 + uint32 indices; no normals: viewers shade flat, which suits
  machined parts), one material per colour (``baseColorFactor``, which glTF 2.0 defines
  as LINEAR RGB: the display colours, sRGB-encoded like the hex codes below and the
  material table, are decoded with :func:`srgb_to_linear`; three.js's GLTFLoader reads
  the factor as linear and its renderer encodes sRGB for the screen);
* units: **metres** (glTF's unit): positions and translations are the model's mm x 1e-3;
  ``asset.extras`` says ``{"units": "m", "source_units": "mm"}``; y is glTF's up axis, so
  the root node turns the model's z-up world R0 into y-up (rotation -90 deg about x);
* when N > 1, one animation ``stroke``: each moving body's translation and rotation at
  the N poses, forward then back (a loop), ``STROKE_PERIOD_S`` seconds in all.

The bytes depend only on the inputs (no time stamps, no random ids).
"""

from __future__ import annotations

import json

import numpy as np

from cad.data.materials import get_material
from cad.export.shapes import make_compound, to_topods
from cad.export.stl import mesh_shape

#: Duration of one forward-and-back stroke in the animation (s).
STROKE_PERIOD_S = 4.0
#: Root rotation (x, y, z, w): R0 is z-up, glTF is y-up -> rotate -90 deg about x.
Z_UP_TO_Y_UP = (-(0.5**0.5), 0.0, 0.0, 0.5**0.5)
#: Colours of the moving bodies of the four-bar (made parts); other bodies cycle PALETTE.
BODY_COLORS = {"ground": "#9aa0a6", "crank": "#d9534f", "coupler": "#337ab7", "rocker": "#5cb85c"}
PALETTE = ("#d9534f", "#337ab7", "#5cb85c", "#f0ad4e", "#8e6cc0", "#5bc0de", "#c7a26b")


def srgb_to_linear(rgb) -> tuple[float, float, float]:
    """Linear RGB of sRGB-encoded ``rgb`` (each 0..1), the IEC 61966-2-1 transfer function:
    c / 12.92 for c <= 0.04045, else ((c + 0.055) / 1.055) ** 2.4."""
    return tuple(c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
                 for c in (float(x) for x in rgb))


def hex_rgb(h: str) -> tuple[float, float, float]:
    """sRGB-encoded (display) colour of ``"#rrggbb"``, each channel 0..1."""
    h = h.lstrip("#")
    return tuple(int(h[i : i + 2], 16) / 255.0 for i in (0, 2, 4))


def body_color_map(bodies) -> dict[str, tuple[float, float, float]]:
    """Display colour of each body (``BODY_COLORS``, else ``PALETTE`` in order)."""
    out, k = {}, 0
    for b in bodies:
        if b in BODY_COLORS:
            out[b] = hex_rgb(BODY_COLORS[b])
        elif b not in out:
            out[b] = hex_rgb(PALETTE[k % len(PALETTE)])
            k += 1
    return out


def instance_rgb(inst, body_rgb: dict) -> tuple[float, float, float]:
    """Made parts take their body's colour (the mechanism reads at a glance); bought parts
    their material's colour (the STEP colour, :data:`cad.data.materials.MATERIALS`)."""
    if inst.kind.made and inst.body in body_rgb:
        return body_rgb[inst.body]
    return tuple(get_material(inst.kind.material).color_rgb)


def visible_solids(shape):
    """``shape`` without the solids enclosed in another solid's bounding box (a bearing's
    balls between its rings): the viewer cannot see them and they are half the triangles
    of a fabrication-fidelity assembly. A single solid is returned as it is."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer


    solids, exp = [], TopExp_Explorer(shape, TopAbs_SOLID)
    while exp.More():
        solids.append(exp.Current())
        exp.Next()
    if len(solids) < 2:
        return shape
    boxes = []
    for s in solids:
        b = Bnd_Box()
        BRepBndLib.Add_s(s, b)
        boxes.append(np.array(b.Get()).reshape(2, 3))
    keep = [
        s
        for i, s in enumerate(solids)
        if not any(
            j != i and np.all(boxes[j][0] < boxes[i][0]) and np.all(boxes[i][1] < boxes[j][1])
            for j in range(len(solids))
        )
    ]
    return make_compound(keep)


def kind_meshes(instances, tolerance_mm: float, angular_tolerance_rad: float) -> dict:
    """``{kind name: (vertices_mm (V, 3), faces (F, 3))}`` of the listed parts (OCCT mesh of
    :func:`visible_solids`)."""
    out = {}
    for inst in instances:
        k = inst.kind
        if k.listed and k.name not in out:
            shape = visible_solids(to_topods(k.shape, k.name))
            out[k.name] = mesh_shape(shape, tolerance_mm, angular_tolerance_rad)
    return out


def _quat_xyzw(R: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(R).as_quat()  # (..., 4) x, y, z, w


def _trs(T: np.ndarray) -> tuple[list[float], list[float]]:
    return (T[:3, 3] * 1e-3).tolist(), _quat_xyzw(T[:3, :3]).tolist()


def _continuous(q: np.ndarray) -> np.ndarray:
    """Flip quaternion signs so consecutive keys interpolate the short way."""
    q = q.copy()
    for i in range(1, len(q)):
        if np.dot(q[i], q[i - 1]) < 0:
            q[i] = -q[i]
    return q


class _Bin:
    """The GLB binary chunk with its buffer views and accessors."""

    def __init__(self, gl):
        self.gl, self.data = gl, bytearray()

    def add(self, arr: np.ndarray, comp: int, typ: str, target=None, minmax=False) -> int:
        import pygltflib as G

        while len(self.data) % 4:
            self.data.append(0)
        raw = np.ascontiguousarray(arr).tobytes()
        self.gl.bufferViews.append(
            G.BufferView(buffer=0, byteOffset=len(self.data), byteLength=len(raw), target=target)
        )
        self.data += raw
        acc = G.Accessor(
            bufferView=len(self.gl.bufferViews) - 1,
            componentType=comp,
            count=int(arr.shape[0]),
            type=typ,
        )
        if minmax:
            flat = arr.reshape(arr.shape[0], -1)
            acc.min, acc.max = flat.min(axis=0).tolist(), flat.max(axis=0).tolist()
        self.gl.accessors.append(acc)
        return len(self.gl.accessors) - 1


def glb_bytes(
    instances,
    tf_pose: dict[str, np.ndarray],
    meshes: dict,
    *,
    name: str,
    stroke: dict[str, np.ndarray] | None = None,
    period_s: float = STROKE_PERIOD_S,
) -> bytes:
    """The ``.glb`` of the assembly (module docstring).

    instances : part instances (unlisted ones are skipped).
    tf_pose : ``{body: (4, 4)}`` world pose of every body in the static scene (mm).
    meshes : :func:`kind_meshes` output (mm).
    stroke : ``{body: (N, 4, 4)}`` world poses over the stroke (mm); N > 1 adds the
        ``stroke`` animation.
    """
    import pygltflib as G

    gl = G.GLTF2(
        asset=G.Asset(generator="hapticad", extras={"units": "m", "source_units": "mm"}),
        scene=0,
        scenes=[G.Scene(name=name, nodes=[0])],
    )
    bin_ = _Bin(gl)
    root = G.Node(name=name, rotation=list(Z_UP_TO_Y_UP), children=[])
    gl.nodes.append(root)
    bodies = list(dict.fromkeys(i.body for i in instances if i.kind.listed))
    body_rgb = body_color_map(bodies)
    mesh_of: dict[str, int] = {}
    mat_of: dict[tuple, int] = {}
    body_node: dict[str, int] = {}
    for b in bodies:
        t, r = _trs(np.asarray(tf_pose[b], dtype=float).reshape(4, 4))
        gl.nodes.append(G.Node(name=f"body:{b}", translation=t, rotation=r, children=[]))
        body_node[b] = len(gl.nodes) - 1
        root.children.append(body_node[b])
    for inst in instances:
        k = inst.kind
        if not k.listed:
            continue
        display = instance_rgb(inst, body_rgb)
        rgb = tuple(round(c, 4) for c in display)
        if rgb not in mat_of:
            gl.materials.append(
                G.Material(
                    name="rgb_" + "".join(f"{int(round(c * 255)):02x}" for c in rgb),
                    pbrMetallicRoughness=G.PbrMetallicRoughness(
                        baseColorFactor=[*srgb_to_linear(display), 1.0], metallicFactor=0.1,
                        roughnessFactor=0.6,
                    ),
                )
            )
            mat_of[rgb] = len(gl.materials) - 1
        key = f"{k.name}|{mat_of[rgb]}"
        if key not in mesh_of:
            v, f = meshes[k.name]
            pos = bin_.add(
                (np.asarray(v) * 1e-3).astype("<f4"), G.FLOAT, G.VEC3, G.ARRAY_BUFFER, True
            )
            idx = bin_.add(
                np.asarray(f, dtype="<u4").reshape(-1),
                G.UNSIGNED_INT,
                G.SCALAR,
                G.ELEMENT_ARRAY_BUFFER,
            )
            prim = G.Primitive(
                attributes=G.Attributes(POSITION=pos), indices=idx, material=mat_of[rgb]
            )
            gl.meshes.append(G.Mesh(name=k.name, primitives=[prim]))
            mesh_of[key] = len(gl.meshes) - 1
        T = np.asarray(inst.tf_body_part, dtype=float).copy()
        T[:3, 3] *= 1e-3
        gl.nodes.append(G.Node(name=inst.name, mesh=mesh_of[key], matrix=T.T.reshape(-1).tolist()))
        gl.nodes[body_node[inst.body]].children.append(len(gl.nodes) - 1)
    if stroke is not None:
        _add_stroke_animation(gl, bin_, bodies, body_node, stroke, period_s)
    gl.buffers.append(G.Buffer(byteLength=len(bin_.data)))
    gl.set_binary_blob(bytes(bin_.data))
    return b"".join(gl.save_to_bytes())


def _add_stroke_animation(gl, bin_, bodies, body_node, tf_world_body, period_s) -> None:
    """Keyframes of every moving body over the stroke, forward then back."""
    import pygltflib as G

    n = len(next(iter(tf_world_body.values())))
    if n < 2:
        return
    order = list(range(n)) + list(range(n - 2, -1, -1))
    times = np.linspace(0.0, period_s, len(order)).astype("<f4")
    t_acc = None
    anim = G.Animation(name="stroke", channels=[], samplers=[])
    for b in bodies:
        T = np.asarray(tf_world_body[b], dtype=float)[order]
        if np.allclose(T, T[0]):
            continue
        if t_acc is None:
            t_acc = bin_.add(times, G.FLOAT, G.SCALAR, minmax=True)
        tr = (T[:, :3, 3] * 1e-3).astype("<f4")
        q = _continuous(_quat_xyzw(T[:, :3, :3])).astype("<f4")
        for path, arr, typ in (("translation", tr, G.VEC3), ("rotation", q, G.VEC4)):
            out = bin_.add(arr, G.FLOAT, typ)
            anim.samplers.append(
                G.AnimationSampler(input=t_acc, output=out, interpolation="LINEAR")
            )
            anim.channels.append(
                G.AnimationChannel(
                    sampler=len(anim.samplers) - 1,
                    target=G.AnimationChannelTarget(node=body_node[b], path=path),
                )
            )
    if anim.channels:
        gl.animations.append(anim)


def glb_json(data: bytes) -> dict:
    """The JSON chunk of a ``.glb`` (for tests and the report)."""
    n = int.from_bytes(data[12:16], "little")
    return json.loads(data[20 : 20 + n])
