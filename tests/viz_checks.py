"""Read-back checks of a build's assembly.glb, shared by the build tests of every family.

The glb is read by trimesh (scene graph) and pygltflib (animation keyframes); what it must
show comes from the design file and report.json, never from the writer.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def keyframes(gl, node_name: str, path: str) -> np.ndarray:
    """(K, 3 | 4) keyframe values of one animated node property (pygltflib document)."""
    node = next(i for i, n in enumerate(gl.nodes) if n.name == node_name)
    (anim,) = gl.animations
    ch = next(c for c in anim.channels if c.target.node == node and c.target.path == path)
    acc = gl.accessors[anim.samplers[ch.sampler].output]
    view = gl.bufferViews[acc.bufferView]
    width = {"VEC3": 3, "VEC4": 4}[acc.type]
    off = view.byteOffset + (acc.byteOffset or 0)
    return np.frombuffer(
        gl.binary_blob(), dtype="<f4", count=width * acc.count, offset=off
    ).reshape(-1, width)


def check_glb(out: Path) -> tuple[object, object, dict]:
    """Common checks; returns (trimesh scene, pygltflib document, report.json)."""
    import pygltflib
    import trimesh

    rep = json.loads((out / "report.json").read_text())
    scene = trimesh.load(out / "assembly.glb")
    gl = pygltflib.GLTF2().load(str(out / "assembly.glb"))
    assert gl.asset.extras["units"] == "m"
    # one mesh node per listed part instance: as many as the BOM's quantities add up to, but
    # for the encoder lines (bought, no modelled solid: cad.device.encoder_bom_rows)
    assert len(scene.graph.nodes_geometry) == sum(r["quantity"] for r in rep["bom"] if r["part"] != "encoder")
    names = set(scene.graph.nodes_geometry)
    assert len(names) == len(scene.graph.nodes_geometry)  # named, no duplicates
    assert len(gl.animations) == 1 and gl.animations[0].name == "stroke"
    return scene, gl, rep


def check_family_glb(out: Path, design_path: Path) -> None:
    """Family-specific: the animation follows the design's motion (mm -> m)."""
    import tomllib

    d = tomllib.loads(Path(design_path).read_text())
    scene, gl, rep = check_glb(out)
    family = d["mechanism"]["family"]
    if family == "powermouse":
        t = keyframes(gl, "body:flotor", "translation") * 1e3  # mm in R0
        q = keyframes(gl, "body:flotor", "rotation")
        rng = d["motion"]["range_mm"]
        for axis in range(3):
            assert np.isclose(t[:, axis].max(), rng, atol=1e-4)
            assert np.isclose(t[:, axis].min(), -rng, atol=1e-4)
        angle = np.degrees(2 * np.arccos(np.clip(np.abs(q[:, 3]), 0, 1)))
        assert np.isclose(angle.max(), d["motion"]["range_deg"], atol=1e-3)
    elif family in ("pantograph", "twin-pantograph"):
        handle = "body:crankshaft" if family == "twin-pantograph" else "body:handle"
        t = keyframes(gl, handle, "translation") * 1e3
        (cx, cy), h = d["workspace"]["center_mm"], d["workspace"]["side_mm"] / 2
        # the handle goes once round the workspace square (R0 x, y in the glb's body frame)
        assert np.allclose([t[:, 0].min(), t[:, 0].max()], [cx - h, cx + h], atol=1e-3)
        assert np.allclose([t[:, 1].min(), t[:, 1].max()], [cy - h, cy + h], atol=1e-3)
        # the animation's poses come from body_poses(); the static scene from the build's
        # assembly(): at the home pose both must place every body the same way
        from scipy.spatial.transform import Rotation

        from cad.design import load_design
        from cad.families.pantograph.build import body_poses

        dd = load_design(design_path)
        home = np.asarray(d["workspace"].get("home_mm", d["workspace"]["center_mm"]), float)
        if family == "twin-pantograph":
            home = np.r_[home, np.radians(d["workspace"]["home_theta_deg"])]
        poses = body_poses(dd, home)
        for n in gl.nodes:
            if n.name and n.name.startswith("body:"):
                T = poses[n.name[5:]][0]
                assert np.allclose(np.array(n.translation) * 1e3, T[:3, 3], atol=1e-6), n.name
                R = Rotation.from_quat(n.rotation).as_matrix()
                assert np.allclose(R, T[:3, :3], atol=1e-9), n.name
