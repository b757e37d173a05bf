"""What a run returns: the saved steps in memory (``Result``; what a saved step holds is
``core.records``) and their post-processing (``timeseries``)."""
