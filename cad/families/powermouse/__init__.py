"""The powermouse family's layout code (:mod:`cad.families`): the maglev PowerMouse.
``assemble(design, fidelity)`` returns the :class:`cad.assembly.model.AssemblyModel`
(instances, centre pose, the flotor's excursions)."""

from cad.families.powermouse.build import assemble

__all__ = ["assemble"]
