"""References and checks: closed-form solutions (``analytic``), spectra, the tangent check."""
