"""Solvers that see only the system's residual/tangent interface."""
