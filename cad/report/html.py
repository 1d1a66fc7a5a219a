"""``report.html``: one self-contained page per build (every family), written by the dispatcher.

What the page holds (nothing is fetched: no network, no file beside it is read):

* the 3D assembly (the build's ``.glb``, :mod:`cad.export.gltf`, base64 inside the page)
  in a three.js viewer the reader can orbit (drag), zoom (wheel) and pan (right drag),
  playing the mechanism's ``stroke`` animation (play/pause, a slider over the stroke);
  three.js is vendored in ``cad/report/vendor/`` and inlined as ``data:`` URLs of an
  import map (see its README.md);
* ``animation.gif`` (the same stroke, rendered without a GPU, :mod:`cad.report.render`);
* every chart of the build (the top-level ``*.png`` files listed in the report);
* first, the device datasheet (``report["datasheet"]``, :mod:`cad.datasheet`): one row per
  figure with its value, model and verdict, every missed limit as a red line above it;
* the fastener records as a table (size, length, parts clamped, hole, engagement);
* the BOM (``report["bom"]``), the assembly steps (``assembly.md`` with each step's
  exploded view, :mod:`cad.report.step_views`), the checks (interference, clearances, targets: every
  ``checks``-like entry of report.json) and the key numbers, and report.json itself.

The viewer sets ``window.hapticadViewer = {ready, meshes, ground_meshes, animations, error}`` once the
model is shown (used by the browser test) and logs nothing on success.
"""

from __future__ import annotations

import base64
import html
import json
from pathlib import Path

from cad.datasheet import fmt_value, verdict_text
from cad.datasheet.limits import loosened_notes
from cad.io.atomic import write_text_atomic

STATIC = Path(__file__).resolve().parent / "vendor"
#: Import-map key -> (vendored file, relative imports in it renamed to map keys).
MODULES = {
    "three/core": ("three.core.min.js", {}),
    "three": ("three.module.min.js", {'"./three.core.min.js"': '"three/core"'}),
    "three/addons/utils/BufferGeometryUtils.js": ("BufferGeometryUtils.js", {}),
    "three/addons/controls/OrbitControls.js": ("OrbitControls.js", {}),
    "three/addons/loaders/GLTFLoader.js": (
        "GLTFLoader.js",
        {"'../utils/BufferGeometryUtils.js'": "'three/addons/utils/BufferGeometryUtils.js'"},
    ),
}
#: Top-level report keys shown as checks, and words that make any key one.
CHECK_KEYS = ("interference", "min_clearance_mm", "overlap_volume_mm3", "targets")
CHECK_WORDS = ("check", "clearance", "collision", "fastener", "target")
#: Pictures shown as charts (in this order first); render.png is the still of the viewer.
CHART_ORDER = ("preview.png", "kinematics.png", "apparent_mass.png")


def _data_url(mime: str, data: bytes) -> str:
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


def import_map() -> str:
    """The import map JSON: every vendored module as a ``data:`` URL."""
    imports = {}
    for key, (fname, renames) in MODULES.items():
        src = (STATIC / fname).read_text(encoding="utf-8")
        for old, new in renames.items():
            if old not in src:
                raise RuntimeError(f"vendored {fname}: expected import {old} not found")
            src = src.replace(old, new)
        imports[key] = _data_url("text/javascript", src.encode("utf-8"))
    return json.dumps({"imports": imports})


VIEWER_JS = r"""
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const state = { ready: false, meshes: 0, ground_meshes: 0, animations: 0, error: null };
window.hapticadViewer = state;
const canvas = document.getElementById('viewer');
const info = document.getElementById('viewer-info');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf4f5f7);
scene.add(new THREE.HemisphereLight(0xffffff, 0x60646c, 1.1));
const sun = new THREE.DirectionalLight(0xffffff, 2.2);
sun.position.set(1, 2, 1.5);
scene.add(sun);
const fill = new THREE.DirectionalLight(0xffffff, 0.8);
fill.position.set(-1.5, 0.5, -1);
scene.add(fill);
const camera = new THREE.PerspectiveCamera(35, 1, 0.001, 100);
const controls = new OrbitControls(camera, canvas);
controls.enableDamping = true;
let mixer = null, action = null, clip = null, playing = true;
const groundMeshes = [];
const GROUND = THREE.PropertyBinding.sanitizeNodeName('body:ground');
const slider = document.getElementById('stroke');
const play = document.getElementById('play');

function resize() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

const bytes = Uint8Array.from(atob(document.getElementById('glb').textContent.trim()), c => c.charCodeAt(0));
new GLTFLoader().parse(bytes.buffer, '', (gltf) => {
  const root = gltf.scene;
  scene.add(root);
  root.traverse(o => {
    if (!o.isMesh) return;
    state.meshes += 1;
    let b = o.parent;  // three.js drops ':' from node names: body:ground -> bodyground
    while (b && b.name !== GROUND && b !== root) b = b.parent;
    if (b && b.name === GROUND) { o.material = o.material.clone(); groundMeshes.push(o); }
    o.material.side = THREE.DoubleSide;
  });
  const box = new THREE.Box3().setFromObject(root);
  const c = box.getCenter(new THREE.Vector3()), r = box.getSize(new THREE.Vector3()).length() / 2;
  camera.position.copy(c).add(new THREE.Vector3(1.2, 0.9, 1.6).normalize().multiplyScalar(r * 3.2));
  camera.near = r / 100; camera.far = r * 100;
  controls.target.copy(c);
  controls.update();
  state.animations = gltf.animations.length;
  state.ground_meshes = groundMeshes.length;
  if (gltf.animations.length) {
    mixer = new THREE.AnimationMixer(root);
    clip = gltf.animations[0];
    action = mixer.clipAction(clip);
    action.play();
  } else {
    play.disabled = true; slider.disabled = true;
  }
  info.textContent = state.meshes + ' parts; drag to orbit, wheel to zoom, right-drag to pan';
  resize();
  renderer.render(scene, camera);
  state.ready = true;
}, (err) => { state.error = String(err); info.textContent = 'could not show the model: ' + err; throw err; });

const xray = document.getElementById('xray');
xray.addEventListener('change', () => {
  for (const o of groundMeshes) {
    o.material.transparent = xray.checked;
    o.material.opacity = xray.checked ? 0.25 : 1.0;
    o.material.depthWrite = !xray.checked;
    o.material.needsUpdate = true;
  }
});
play.addEventListener('click', () => { playing = !playing; play.textContent = playing ? 'pause' : 'play'; });
slider.addEventListener('input', () => {
  if (!mixer) return;
  playing = false; play.textContent = 'play';
  mixer.setTime(clip.duration * slider.value / 1000);
});
const clock = new THREE.Clock();
renderer.setAnimationLoop(() => {
  const dt = clock.getDelta();
  if (mixer && playing) {
    mixer.update(dt);
    slider.value = Math.round(1000 * (action.time % clip.duration) / clip.duration);
  }
  controls.update();
  renderer.render(scene, camera);
});
"""

CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:0 auto;max-width:1100px;padding:0 16px 40px;color:#222}
h1{margin:18px 0 4px} h2{margin-top:28px;border-bottom:1px solid #ddd}
#viewer{width:100%;height:520px;display:block;border:1px solid #ccc;border-radius:4px;background:#f4f5f7}
.controls{display:flex;gap:10px;align-items:center;margin:6px 0}
#stroke{flex:1}
table{border-collapse:collapse;font-size:14px} td,th{border:1px solid #ddd;padding:3px 8px;text-align:left}
td.num{text-align:right;font-variant-numeric:tabular-nums}
.ok{color:#1a7f37;font-weight:600} .bad{color:#c62828;font-weight:600} .warn{color:#a15c00;font-weight:600}
img.chart{max-width:100%;border:1px solid #eee;margin:6px 0}
img.step{max-width:100%;border:1px solid #eee}
pre{background:#f6f8fa;padding:8px;overflow:auto;max-height:480px;font-size:12px}
.muted{color:#666;font-size:13px}
"""


#: Longest text of a nested value in a table cell (characters; the rest in report.json).
CELL_CHARS = 300


def _fmt(v, depth: int = 0) -> str:
    """A value as table text: numbers to 6 significant digits, lists comma-separated,
    dicts as ``key: value; ...`` (nested ones in parentheses), never JSON; cut at
    :data:`CELL_CHARS`."""
    if v is None:
        return "none"
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        text = ", ".join(_fmt(x, depth + 1) for x in v) if v else "none"
        return f"({text})" if depth and len(v) > 1 else text
    if isinstance(v, dict):
        text = "; ".join(f"{k}: {_fmt(x, depth + 1)}" for k, x in v.items()) if v else "none"
        text = f"({text})" if depth and v else text
    else:
        text = str(v)
    return text if depth or len(text) <= CELL_CHARS else text[: CELL_CHARS - 1] + "…"


def _table(rows: list[list], head: list[str]) -> str:
    th = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    body = []
    for r in rows:
        tds = []
        for c in r:
            if isinstance(c, tuple):  # (text, css class)
                tds.append(f'<td class="{c[1]}">{html.escape(c[0])}</td>')
            else:
                cls = (
                    ' class="num"'
                    if isinstance(c, (int, float)) and not isinstance(c, bool)
                    else ""
                )
                tds.append(f"<td{cls}>{html.escape(_fmt(c))}</td>")
        body.append("<tr>" + "".join(tds) + "</tr>")
    return f"<table><tr>{th}</tr>{''.join(body)}</table>"


def bom_table(report: dict) -> str:
    bom = report.get("bom") or []
    if not bom:
        return '<p class="muted">This build lists no BOM.</p>'
    cols = list(dict.fromkeys(k for row in bom for k in row))
    return _table([[row.get(c, "") for c in cols] for row in bom], cols)


def _verdict(key: str, v) -> tuple[str, str] | None:
    """Pass/fail of a check value where the report states it."""
    if isinstance(v, dict):
        if "collisions" in v:
            n = len(v["collisions"] or [])
            return ("no collision", "ok") if n == 0 else (f"{n} collision(s)", "bad")
        for k in ("ok", "passed", "pass", "within_tolerance"):
            if isinstance(v.get(k), bool):
                return ("pass", "ok") if v[k] else ("FAIL", "bad")
    if key == "overlap_volume_mm3" and isinstance(v, (int, float)):
        return ("no overlap", "ok") if v == 0 else ("overlap", "bad")
    return None


def checks_rows(report: dict) -> list[list]:
    """``[check, value, verdict]`` for every checks-like entry of the report (one level of
    nesting: a dict's items become rows ``key.item``)."""
    rows = []
    keys = [k for k in report if k in CHECK_KEYS or any(w in k.lower() for w in CHECK_WORDS)]
    for k in keys:
        v = report[k]
        verdict = _verdict(k, v)
        expand = isinstance(v, dict) and k not in ("interference", "fasteners", "tapped_holes")
        text = f"{len(v)} entries (rows below)" if expand and v else _summary(v)
        rows.append([k, text, verdict or ("", "")])
        if expand:
            for sk, sv in v.items():
                rows.append([f"{k}.{sk}", _summary(sv), _verdict(sk, sv) or ("", "")])
                if isinstance(sv, dict) and sv and all(isinstance(x, dict) for x in sv.values()):
                    rows += [[f"{k}.{sk}.{n}", _summary(x), _verdict(n, x) or ("", "")]
                             for n, x in sv.items()]  # records by name: one row each
    return rows


def _summary(v) -> str:
    if isinstance(v, dict) and v and all(isinstance(x, dict) and "size" in x for x in v.values()):
        return f"{len(v)} records (table below)"
    if isinstance(v, dict) and v and all(isinstance(x, dict) for x in v.values()):
        return f"{len(v)} records (rows below)"
    if isinstance(v, dict) and "collisions" in v:
        keep = {
            k: v[k] for k in ("min_clearance_mm", "overlap_volume_mm3", "method", "poses") if k in v
        }
        keep["collisions"] = v["collisions"]
        return _fmt(keep)
    return _fmt(v)


def key_numbers(report: dict) -> list[list]:
    out = []
    for k, v in report.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out.append([k, v])
        elif isinstance(v, dict) and k in ("apparent_mass", "gii", "effective_mass_home"):
            out += [[f"{k}.{sk}", sv] for sk, sv in v.items() if isinstance(sv, (int, float))]
    return out


def charts(report: dict, out_dir: Path) -> list[tuple[str, bytes]]:
    """``[(file name, PNG bytes)]`` of the build's top-level pictures (charts first)."""
    names = [f for f in report.get("files", []) if f.endswith(".png") and "/" not in f]
    names += [p.name for p in sorted(Path(out_dir).glob("*.png")) if p.name not in names]
    names = [n for n in names if n != "render.png"]
    ordered = [n for n in CHART_ORDER if n in names] + sorted(
        n for n in names if n not in CHART_ORDER
    )
    return [(n, (Path(out_dir) / n).read_bytes()) for n in ordered if (Path(out_dir) / n).is_file()]


def datasheet_html(report: dict) -> str:
    """The datasheet section: missed limits in red first, then the table (empty string
    when the report has no datasheet)."""
    ds = report.get("datasheet")
    if not ds:
        return ""
    out = ["<h2>Datasheet</h2>"]
    if ds.get("warnings"):
        out.append("<ul>" + "".join(f"<li class='bad'>warning: {html.escape(w)}</li>" for w in ds["warnings"])
                   + "</ul>")
    else:
        out.append("<p class='ok'>every figure with a limit meets it</p>")
    loose = loosened_notes(ds["rows"])
    if loose:
        out.append("<ul>" + "".join(f"<li class='warn'>{html.escape(n)}</li>" for n in loose) + "</ul>")
    rows = []
    for r in ds["rows"]:
        model = r["model"] + (f"; {r['boundary']}" if r["boundary"] else "")
        if r["unverified"]:
            model += " (uses unverified data)"
        if r.get("paper"):
            model += f"; paper: {r['paper']}"
        cls = {"ok": "ok", "miss": "bad"}.get(r["verdict"], "")
        rows.append([r["figure"], (fmt_value(r), "num"), r["unit"], model, (verdict_text(r), cls)])
    out.append(_table(rows, ["figure", "value (min .. max)", "unit", "model / source", "verdict"]))
    out += [f"<p class='muted'>{html.escape(n)}</p>" for n in ds.get("notes", ()) if n not in loose]
    return "".join(out)


def fastener_table(report: dict) -> str:
    """The fastener records (:func:`cad.pipeline.family.fastener_report`) as a readable table."""
    fast = report.get("fasteners") or {}
    if not fast:
        return ""
    rows = []
    for name, f in sorted(fast.items()):
        clamps = f.get("clamps", [])
        rows.append([name, f.get("kind", ""), f.get("size", ""), f.get("length_mm", ""),
                     ", ".join(clamps) if isinstance(clamps, list) else str(clamps), f.get("hole", ""),
                     f.get("engagement_mm", "")])
    return "<h2>Fasteners</h2>" + _table(rows, ["screw", "standard", "size", "length (mm)", "clamps",
                                                "hole engaged", "engagement (mm)"])


def _md_inline(text: str) -> str:
    """Escaped text with ``code`` spans of assembly.md as <code>."""
    bits = html.escape(text).split("`")
    return "".join(f"<code>{b}</code>" if k % 2 else b for k, b in enumerate(bits))


def assembly_steps_html(out_dir: Path) -> str:
    """The "Assembly steps" section: ``assembly.md`` of the build (written by
    :func:`cad.pipeline.family.write_assembly_md`: ``## Step`` headings, ``- `` bullets and
    the exploded view of each step, ``![alt](steps/step_NN.png)``, embedded here); empty
    when the build wrote no assembly.md."""
    import re

    md = Path(out_dir) / "assembly.md"
    if not md.is_file():
        return ""
    out, items = ["<h2>Assembly steps</h2>"], []

    def close() -> None:
        if items:
            out.append("<ul>" + "".join(f"<li>{i}</li>" for i in items) + "</ul>")
            items.clear()

    for line in md.read_text(encoding="utf-8").splitlines()[1:]:
        img = re.fullmatch(r"!\[([^\]]*)\]\((steps/step_\d+\.png)\)", line)
        if line.startswith("## "):
            close()
            out.append(f"<h3>{_md_inline(line[3:])}</h3>")
        elif line.startswith("- "):
            items.append(_md_inline(line[2:]))
        elif img and (Path(out_dir) / img[2]).is_file():
            close()
            data = _data_url("image/png", (Path(out_dir) / img[2]).read_bytes())
            out.append(f"<figure><img class='step' alt='{html.escape(img[1])}' src='{data}'>"
                       f"<figcaption class='muted'>{html.escape(img[2])}</figcaption></figure>")
        elif line.strip():
            close()
            out.append(f"<p class='muted'>{_md_inline(line)}</p>")
    close()
    return "".join(out)


def report_html(report: dict, out_dir: Path, glb: bytes | None) -> str:
    """The page (module docstring) for ``report`` (report.json's content) built in ``out_dir``."""
    out_dir = Path(out_dir)
    name = html.escape(str(report.get("name", out_dir.name)))
    family = html.escape(str(report.get("family", "")))
    parts = [
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{name}: hapticad build report</title><style>{CSS}</style>",
    ]
    if glb is not None:
        parts.append(f'<script type="importmap">{import_map()}</script>')
    parts.append("</head><body>")
    parts.append(f"<h1>{name} <span class='muted'>({family})</span></h1>")
    b = report.get("build", {})
    parts.append(
        f"<p class='muted'>hapticad build of <code>{html.escape(str(report.get('source', '')))}</code>; "
        f"fidelity {html.escape(str(b.get('fidelity', report.get('fidelity', ''))))}; "
        f"formats {html.escape(', '.join(b.get('formats', [])))}. Lengths in mm unless a key says otherwise.</p>"
    )
    parts.append(datasheet_html(report))
    parts.append("<h2>Assembly (3D)</h2>")
    if glb is not None:
        parts.append(
            "<canvas id='viewer'></canvas><div class='controls'><button id='play'>pause</button>"
            "<input id='stroke' type='range' min='0' max='1000' value='0' aria-label='position over the stroke'>"
            "<span class='muted'>stroke</span><label class='muted'><input id='xray' type='checkbox'> see through the frame</label></div><p id='viewer-info' class='muted'>loading the model…</p>"
            f"<script type='application/octet-stream' id='glb'>{base64.b64encode(glb).decode('ascii')}</script>"
            f"<script type='module'>{VIEWER_JS}</script>"
        )
    else:
        parts.append("<p class='muted'>No 3D model for this family's build.</p>")
    gif = out_dir / "animation.gif"
    if gif.is_file():
        parts.append(
            "<h2>The stroke</h2><p class='muted'>animation.gif (beside this file), rendered without a GPU.</p>"
            f"<img class='chart' alt='the mechanism over its stroke' src='{_data_url('image/gif', gif.read_bytes())}'>"
        )
    ch = charts(report, out_dir)
    if ch:
        parts.append("<h2>Charts</h2>")
        for n, data in ch:
            parts.append(
                f"<figure><img class='chart' alt='{html.escape(n)}' src='{_data_url('image/png', data)}'>"
                f"<figcaption class='muted'>{html.escape(n)}</figcaption></figure>"
            )
    parts.append("<h2>Checks</h2>")
    rows = checks_rows(report)
    parts.append(
        _table(rows, ["check", "value", "verdict"])
        if rows
        else "<p class='muted'>none reported</p>"
    )
    parts.append(fastener_table(report))
    parts.append("<h2>Bill of materials</h2>" + bom_table(report))
    parts.append(assembly_steps_html(out_dir))
    parts.append("<h2>Key numbers</h2>" + _table(key_numbers(report), ["key", "value"]))
    parts.append(
        "<h2>report.json</h2><details><summary>show</summary><pre>"
        + html.escape(json.dumps(report, indent=1, sort_keys=True, default=str))
        + "</pre></details></body></html>"
    )
    return "\n".join(parts) + "\n"


def write_report_html(report: dict, out_dir: Path, glb: bytes | None) -> Path:
    """Write ``out_dir/report.html`` atomically."""
    return write_text_atomic(Path(out_dir) / "report.html", report_html(report, out_dir, glb))
