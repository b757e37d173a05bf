"""numba kernels.  Importing this package (``skfem_cable`` does it first) puts numba's
cache of the package's functions into the cache folder (``cache``) and reports what numba
compiles (``compile_log``).

The element kernels are written for any number of element functions ``nf`` (the last
dimension of their tables: ``elements``).  Those of the line loads (the solar wind, the
drag, the electrodynamic force), whose work per point is light, are generated per ``nf``
(``line.module``: its loops unrolled, as fast as code written for the element): reading
``nf`` from the tables cost the E-sail's step 3 %.
The laws' kernels (``cable``) read it, their point functions dominating; the assumed
strain's (``assumed_strain``) is compiled per element type, with its sizes and map
fixed (read from the tables they cost the cubic a fifth more time per evaluation and the
quintic a half).
"""

from . import cache, compile_log

#: The functions of the paper's cubic element, for which the element kernels compile a
#: specialised copy.
CUBIC = 4

cache.install()
compile_log.install()
