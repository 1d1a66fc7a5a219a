"""The family protocol: what one family package gives the rest of hapticad.

Every package ``cad/families/<package>/`` exports one :class:`FamilyPackage` named ``FAMILY``
from its ``__init__``; the registry row (:mod:`cad.data.families`) names the package, and
:func:`cad.families.family_package` returns its ``FAMILY``. Everything that is not the
family's own -- the build driver and the file writers (:mod:`cad.pipeline`), the datasheet's
judging and layout (:mod:`cad.datasheet`), ``check``/``fit``/``optimize`` (:mod:`cad.api`),
the firmware generator (:mod:`cad.firmware`) -- reads the family through these hooks and
never asks which family it is.

Hooks are plain callables. :class:`Lazy` names one as ``"module:attribute"`` and imports it
on its first call, so importing a package (the CLI's start-up, the registry) loads no layout
or CAD code and no import cycle through :mod:`cad.pipeline` can form.

No CAD imports.
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Callable
from typing import Any


class Lazy:
    """A callable named ``"package.module:attribute"``, imported on its first call.

    ``Lazy("cad.families.fourbar.build:build")(design, ...)`` is
    ``cad.families.fourbar.build.build(design, ...)``. Raises what the import or the call
    raises (ModuleNotFoundError, AttributeError for a wrong name)."""

    __slots__ = ("ref", "_fn")

    def __init__(self, ref: str):
        if ref.count(":") != 1:
            raise ValueError(f"expected 'module:attribute', got {ref!r}")
        self.ref, self._fn = ref, None

    def resolve(self) -> Any:
        """The named object (imported once)."""
        if self._fn is None:
            module, attr = self.ref.split(":")
            self._fn = getattr(importlib.import_module(module), attr)
        return self._fn

    @property
    def module(self) -> str:
        """The module the hook lives in."""
        return self.ref.split(":")[0]

    def __call__(self, *args, **kwargs):
        return self.resolve()(*args, **kwargs)

    def __repr__(self) -> str:
        return f"Lazy({self.ref!r})"


Hook = Callable[..., Any]


@dataclasses.dataclass(frozen=True)
class TargetHooks:
    """How ``check``, ``fit`` and ``optimize`` evaluate a family's designs against targets.

    keys : the target keys its designs take (:mod:`cad.design.targets`).
    values : ``values(design, fidelity, wanted: set[str]) -> (values, report)``: the flat
        ``{key: value}`` of the wanted targets (and any others computed on the way) and the
        build or model report they came from.
    parse_free : ``parse_free(spec: str, design) -> cad.studies.fit.FreeParam`` (``--free``;
        DesignError naming ``--free``).
    blockers : ``blockers(design, report, rows) -> list[str]``: for missed target rows, the
        lines saying what in the layout blocks them and the best figure reachable (may be
        empty).
    fit_limits : ``fit_limits(design) -> tuple[Target]``: the default datasheet limits every
        fit candidate must also meet (None: the targets only).
    precad : ``precad(design) -> (values, reason | None)``: checks before any CAD that
        reject a fit candidate (None: none).
    fit_values : ``fit_values(design, fidelity, wanted)`` as ``values``, for one ``fit``
        candidate (None: ``values``).
    """

    keys: tuple[str, ...]
    values: Hook
    parse_free: Hook
    blockers: Hook | None = None
    fit_limits: Hook | None = None
    precad: Hook | None = None
    fit_values: Hook | None = None


@dataclasses.dataclass(frozen=True)
class FamilyPackage:
    """One family package (the object ``FAMILY`` of ``cad/families/<package>/__init__.py``).

    package : the package name under ``cad.families``.
    assemble : ``assemble(design, fidelity) -> cad.assembly.model.AssemblyModel`` (None: the
        family has no parts yet; ``build`` and ``assemble`` refuse it in one line).
    build : ``build(design, out_dir, formats, *, fidelity, allow_interference, progress,
        phi1_deg) -> report dict`` (the contract in :mod:`cad.pipeline`): one call to the
        build driver :func:`cad.pipeline.run.run_family` with the family's stages.
    check_options : ``check_options(design, fidelity, phi1_deg, formats)``: DesignError for
        a combination the family cannot build, before any CAD import.
    check_layout : ``check_layout(design, fidelity, allow_interference)``: DesignError for a
        layout that cannot clear (before any CAD import), or None.
    code_deps : the ``cad`` sources the build output depends on (the cache key).
    cache_inputs : ``cache_inputs(design) -> dict``: anything outside the design object the
        output depends on (a user part script's hash), or None.
    sim_formats : the simulator formats the build writes (``{"mjcf", "urdf"}`` or a subset).
    view_formats : the build writes ``glb`` / ``3mf``.
    datasheet_rows : ``rows_and_limits(design, report, out_dir, simulate_wall) -> (rows,
        limits, charts)``: the family's rows of the device datasheet (:mod:`cad.datasheet`).
    targets : :class:`TargetHooks`, or None (``check``/``fit`` refuse the family).
    optimize : ``optimize(design, options: dict) -> dict`` (the ``hapticad optimize --json``
        object; ``options``: method, objective, trials, seed, exact_top, proportions_tol,
        starts, beat_prototype; DesignError naming a flag the family does not take), or None.
    firmware : ``firmware(design, report, design_hash, device) -> {path: text}`` (the files
        under ``firmware/``, :mod:`cad.firmware`), or None (no firmware).
    firmware_model : ``firmware_model(design) -> cad.firmware.model.KinematicModel``: the
        linkage's kinematic model :func:`cad.firmware.linkage_files` generates from, or None.
    report_type : the ``TypedDict`` (extending :class:`cad.report.contract.CommonReport`) its
        ``report.json`` keeps to, checked before a build is published; None: the common keys
        only.
    """

    package: str
    build: Hook | None = None
    assemble: Hook | None = None
    check_options: Hook | None = None
    check_layout: Hook | None = None
    code_deps: tuple[str, ...] | None = None
    cache_inputs: Hook | None = None
    sim_formats: frozenset[str] = frozenset()
    view_formats: bool = False
    datasheet_rows: Hook | None = None
    targets: TargetHooks | None = None
    optimize: Hook | None = None
    firmware: Hook | None = None
    firmware_model: Hook | None = None
    report_type: Hook | None = None
