"""The near-Earth environment of a tether: epochs and frames, the geomagnetic field,
the ionosphere, the neutral atmosphere, and the OML current along a bare tether.

* ``Epoch`` (module ``epoch``): the run's ``t = 0`` and the GCRS -> ITRS rotation (astropy),
  ``corotation_velocity`` of the co-rotating medium; ``as_epoch`` (an epoch from a
  datetime, an astropy ``Time`` or a string) and ``bound_model`` (a model at the epoch
  of the system whose load it serves);
* ``IGRF`` (module ``igrf``): the geomagnetic field (ppigrf) with its gradient, the
  protocol of ``MagneticDipole``;
* ``MSIS`` (module ``msis``): the neutral mass density (pymsis, NRLMSIS 2.1);
* ``IRI`` (module ``iri``): the electron density (PyIRI), ``UniformPlasma`` (module
  ``plasma``);
* ``open_circuit_emf`` (module ``emf``): the open-circuit EMF of a straight tether
  along an orbit at an epoch (TSS-1R);
* ``BareTether``, ``Cathode``, ``OMLProblem``, ``OMLProfile``, ``motional_field``
  (module ``oml``): the OML current and bias along a bare tether.

The libraries (ppigrf, pymsis, PyIRI, astropy) are the optional extra ``space``
(``pip install -e .[space]``); they are imported when a model is first used.
"""

from .emf import open_circuit_emf
from .epoch import Epoch, as_epoch, bound_model, corotation_velocity
from .igrf import IGRF
from .iri import IRI
from .msis import MSIS
from .oml import BareTether, Cathode, OMLProblem, OMLProfile, motional_field
from .plasma import UniformPlasma

__all__ = ["BareTether", "Cathode", "Epoch", "IGRF", "IRI", "MSIS", "OMLProblem",
           "OMLProfile", "UniformPlasma", "as_epoch", "bound_model", "corotation_velocity",
           "motional_field", "open_circuit_emf"]
