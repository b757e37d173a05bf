"""The assembled system: bodies, loads and constraints on one coordinate vector
(``System``), its fixed pattern (``layout``), its motions, the labels and the
fingerprint of what defines it, and a configuration (``State``)."""
