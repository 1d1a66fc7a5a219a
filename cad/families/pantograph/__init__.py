"""The pantograph family's layout code (:mod:`cad.families`): the plain 5-bar and the
twin-pantograph haptic mouse. ``assemble(design, fidelity)`` returns the
:class:`cad.assembly.model.AssemblyModel` (instances, home pose, workspace motion)."""

from cad.families.pantograph.build import assemble

__all__ = ["assemble"]
