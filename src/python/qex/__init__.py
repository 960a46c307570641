"""qex: quad meshes from triangle meshes carrying an integer-grid map (QEx).

The map is given per triangle corner, as quad-meshing parametrizers (MIQ, QuadCover, ...) write
it. Arrays follow numpy's conventions:

>>> import qex
>>> V, F, UV = qex.read_obj("corpus/fuzz_obj/valid/cube_n3_k4.obj")
>>> r = qex.extract(V, F, UV)
>>> r.valid, r.quads.shape
(True, (54, 4))

Functions
---------
extract    the quad mesh of a map, with the report and the checker's verdict
verify     judge an extracted result again (exact checker)
check      judge any quad mesh, given as arrays, against a map (the oracle of other extractors)
layout     the patch layout of a quad mesh: separatrices, patches, their sizes and neighbours
read_obj   read an OBJ map as (V, F, UV)
read_vval  read a VVAL file of valences (one per input vertex)
write_obj  write an extracted mesh as OBJ
write_certificate  write the repaired map an extracted mesh is judged on (check(certificate=...))
conform    judge a Python extractor on known, hostile and your own maps, on Dask (qex conform)

Bad input raises ValueError with the library's message, which names the element at fault. The
library releases the GIL while it works, so extractions in several Python threads run in parallel.
"""

from __future__ import annotations

# Each part lives in its own module (extraction, checking, patch_layout, files, conformance);
# the names are re-exported here, so users call qex.extract and never the modules.
from .checking import check, verify
from .conformance import conform
from .extraction import Result, extract
from .files import read_obj, read_vval, write_certificate, write_obj
from .patch_layout import layout

__all__ = ["Result", "extract", "verify", "check", "layout", "read_obj", "read_vval", "write_obj", "write_certificate",
           "conform"]
