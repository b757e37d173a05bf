"""Regenerate docs/figures/thrust_laws.png: the E-sail thrust laws side by side
(``skfem_cable.plot.thrust_laws.laws_figure``).  Run from the repository root:
``python scripts/thrust_laws_figure.py``."""

from pathlib import Path

from skfem_cable.plot.thrust_laws import laws_figure

if __name__ == "__main__":
    out = Path(__file__).resolve().parents[1] / "docs" / "figures" / "thrust_laws.png"
    laws_figure(out)
    print(out)
