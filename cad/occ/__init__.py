"""Thin wrappers of the OCCT calls (OCP) that the layers above the part scripts need.

Issue 23: besides ``cad/parts/`` (part scripts, the shape cache), ``cad/massprops/occt.py``
(exact and mesh mass properties, STEP reading for ``hapticad massprops``) and
``cad/export/`` (file writers, shop drawings), this is the only package that imports OCP or
build123d (``tests/architecture/test_import_graph.py``). One module per concern:

* :mod:`cad.occ.bbox` -- tight bounding boxes;
* :mod:`cad.occ.distance` -- exact distance (``BRepExtrema_DistShapeShape``) and common
  volume (``BRepAlgoAPI_Common``) of two solids, for the interference check;
* :mod:`cad.occ.boolean` -- serial Booleans (common, section) on copies of shared
  part solids (the check and the exports leave a solid as they found it);
* :mod:`cad.occ.shape_io` -- BREP text of a shape (the derived cache's digest);
* :mod:`cad.occ.compound` -- the labelled build123d ``Compound`` of an assembly model;
* :mod:`cad.occ.threads` -- OCCT's thread pool.

Every module imports OCP inside its functions (``import build123d`` costs about 3 s; ``import
cad`` and the light commands load no CAD library, ``tests/api/test_api.py``). Shapes are OCP
``TopoDS_Shape`` in millimetres.
"""
