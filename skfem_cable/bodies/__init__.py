"""Bodies: what has coordinates (the ANCF cable and its fields, formulations and forms; the
rigid body; the reel) and the cross-section."""
