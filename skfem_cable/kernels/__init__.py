"""numba kernels.  Importing this package (``skfem_cable`` does it first) puts numba's
cache of the package's functions into the cache folder (``cache``) and reports what numba
compiles (``compile_log``)."""

from . import cache, compile_log

cache.install()
compile_log.install()
