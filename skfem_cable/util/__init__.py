"""Leaves that know nothing of cables: crash-safe files (``atomic``), durations as users
write them, Python values for JSON files."""
