"""Scenes: functions that build systems and initial states for classic problems."""
