"""The identification report page (issue 37): ``identify.md`` with the fit and residual plots
(``identify_fit.svg``, ``identify_residual.svg``), beside ``identify.json``."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.io.atomic import write_text_atomic
from cad.io.figures import save_figure

FILES = ("identify.json", "identify.md", "identify_fit.svg", "identify_residual.svg")


def _plots(fit, out: Path) -> None:
    """The fit and residual plots: one column per motor, or (an over-actuated device: the
    view's ``labels``) per independent coordinate, the equations W^T tau."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = fit.t_s
    m = fit.mask
    meas, model = np.asarray(fit.tau_meas).reshape(len(t), -1), np.asarray(fit.tau_fit).reshape(len(t), -1)
    many = meas.shape[1] > 1  # one column per motor (the 5-bar: two)
    labels = getattr(fit, "labels", None) or [f"motor {j}" for j in range(meas.shape[1])]
    ylabel = getattr(fit, "ylabel", None) or ("torque at each motor's joint (mN m)" if many else
                                              "torque on the crank (mN m)")
    fig, ax = plt.subplots(figsize=(9, 3.5))
    for j in range(meas.shape[1]):
        who = f"{labels[j]}: " if many else ""
        ax.plot(t, 1e3 * meas[:, j], lw=0.6, label=f"{who}measured s Kt i (filtered)")
        ax.plot(t[m], 1e3 * model[m, j], ".", ms=1.0, label=f"{who}model with the identified parameters")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    save_figure(fig, out / "identify_fit.svg")
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(9, 3.0))
    for j in range(meas.shape[1]):
        ax.plot(t[m], 1e3 * (meas[m, j] - model[m, j]), ".", ms=1.0, label=labels[j] if many else None)
    if many:
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("residual (" + ylabel.rsplit("(", 1)[-1] if "(" in ylabel else "residual")
    fig.tight_layout()
    save_figure(fig, out / "identify_residual.svg")
    plt.close(fig)


def _fmt(v) -> str:
    return "-" if v is None else (f"{v:.4g}" if isinstance(v, float) else str(v))


def page(res: dict) -> str:
    """Markdown of the result ``res`` (:func:`cad.sim.identify_device.identify`)."""
    lines = [f"# Identification of {res['design']}", ""]
    if not res.get("hash_matches", True):
        lines += [f"**The log names design hash {res['log_design_hash'][:12]}..., not this design's "
                  f"{res['design_hash'][:12]}...: it was recorded with another design.**", ""]
    if res.get("stopped"):
        lines += [f"The routine stopped {res['stopped']}; nothing else was identified.", ""]
    lines += ["| figure | what | measured | 1 sigma | unit | predicted | verdict | what would explain a miss |",
              "|---|---|---|---|---|---|---|---|"]
    for r in res["figures"]:  # the key as identify.json, the terminal and docs/identify.md name it
        lines.append(f"| `{r['key']}` | {r.get('what', '')} | {_fmt(r.get('value'))} | {_fmt(r.get('sigma'))} | "
                     f"{r.get('unit', '')} | {_fmt(r.get('predicted'))} | {r['verdict']} | {r.get('explain', '')} |")
    if "delay_samples" in res:
        lines += ["", f"Model: `{res['model']}`; delay {res['delay_samples']} periods; rms residual "
                  f"{res['rms_residual_mNm']:.3g} mN m over {res['rows_fitted']} rows; friction predicted from "
                  f"{res['friction_source']}.", "", "![fit](identify_fit.svg)", "",
                  "![residual](identify_residual.svg)"]
    return "\n".join(lines) + "\n"


def write(res: dict, fit, out: Path) -> list[str]:
    """Write the report page, the plots (when there is a fit) and ``identify.json`` into
    ``out`` (atomically, file by file); return the names written."""
    import json


    out.mkdir(parents=True, exist_ok=True)
    names = ["identify.json", "identify.md"]
    if fit is not None:
        _plots(fit, out)
        names += ["identify_fit.svg", "identify_residual.svg"]
    write_text_atomic(out / "identify.md", page(res))
    write_text_atomic(out / "identify.json", json.dumps(_plain(res), indent=1))
    return names


def _plain(x):
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        return x.item()
    return x
