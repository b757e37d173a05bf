"""The demo gallery: an MkDocs hook that writes the page ``gallery.md`` at build time, and
the script that draws its pictures.

Each entry of ``ENTRIES`` is one file of ``demos/``: its picture (a PNG committed under
``docs/figures/gallery/``), the one number its test checks with the tolerance, the test
and the command that runs it.  The page text comes from the demo itself, its module
docstring (a scene file: its leading comment block), read without importing or running
it, so the docs build stays fast (``mkdocs.yml``: ``hooks: [scripts/gallery.py]``).

The pictures are drawn once, by running the demos (about two minutes; the E-sail reuses
the run directory ``runs/esail`` of ``python3 tasks.py demo`` when it holds a complete
run).  Each demo script draws its own picture (its ``gallery_figure(path)``); this script
only runs it, checks the size, and draws the pictures of the scene files (TOML, no code of
their own)::

    .venv/bin/python scripts/gallery.py              # every picture
    .venv/bin/python scripts/gallery.py kapitza      # one demo

``tests/test_docs.py`` checks that every demo has an entry, that every picture exists and
stays small, and that every test an entry names exists.
"""

import ast
import re
import sys
from dataclasses import dataclass
from functools import partial
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
DEMOS = ROOT / "demos"
#: Folder of the pictures, relative to ``docs/``.
FIGURES = "figures/gallery"
#: Largest picture size (bytes).
MAX_BYTES = 150_000


@dataclass(frozen=True)
class Entry:
    """One demo of the gallery.

    Attributes
    ----------
    demo : str
        File name in ``demos/``.
    check : str
        The number the test checks (Markdown).
    tolerance : str
        Its tolerance (Markdown).
    test : str
        ``tests/FILE.py::FUNCTION``, the test that checks it.
    caption : str
        What the picture shows.
    """

    demo: str
    check: str
    tolerance: str
    test: str
    caption: str

    @property
    def name(self):
        """The demo's name: its file name without the suffix."""
        return Path(self.demo).stem

    @property
    def picture(self):
        """The picture, relative to ``docs/``."""
        return f"{FIGURES}/{self.name}.png"

    @property
    def command(self):
        """The command that runs the demo."""
        if self.demo.endswith(".toml"):
            return f"skfem-cable run demos/{self.demo} --out runs/{self.name}"
        return f"python demos/{self.demo}"


ENTRIES = (
    Entry("cantilever.py",
          "relative error of the tip shortening and deflection against the elliptic-integral "
          "elastica, 8 elements, `k = P L^2 / EI = 2`",
          "< 1e-2", "tests/test_demos.py::test_cantilever_demo",
          "Deformed cantilevers for k = 1, 2, 5 and 10 (16 elements); crosses: the exact tips."),
    Entry("pendulum.py",
          "first passage through the vertical (a quarter period) against the rigid compound "
          "pendulum, 4 elements, `dt = 2e-3 s`",
          "relative 1e-3", "tests/test_demos.py::test_pendulum_demo",
          "Shapes every 0.05 s until the first passage through the vertical, and the tip's "
          "horizontal position against the rigid bar's quarter period."),
    Entry("spinning_tether.py",
          "period of the radial oscillation of the tip mass against the spring-mass "
          "estimate `2 pi / omega_r`, 4 elements, 0.5 s",
          "relative 3e-2", "tests/test_demos.py::test_spinning_tether_demo",
          "Tip radius and root tension over 0.5 s (10 elements) against the steady values."),
    Entry("custom_element.py",
          "tip stretch of the bar of the Biot law pulled by `P = 0.1 EA`: exactly "
          "`P L / EA = 0.1`",
          "relative 1e-8", "tests/test_demos.py::test_custom_element_demo",
          "Tip stretch against the pull for the Biot law (the four-line law) and the "
          "built-in Green law; line: `P L / EA`."),
    Entry("law_gallery.py",
          "tip stretch of the polymer tether pulled by `P = 0.02 EA` against "
          "`e0 ln(1 + P / (EA e0))` (the test also checks no force when slack and the energy "
          "balance of the power-law damping)",
          "relative 1e-9", "tests/test_demos.py::test_law_gallery",
          "Polymer tether: stretch against pull, computed (dots) and exact (line); power-law "
          "damping: energy of the released bar and what it dissipated."),
    Entry("drag_terminal_speed.py",
          "fall speed after 40 time constants against the terminal speed `rho A g / c`, with "
          "the exact and with the finite-difference Jacobian",
          "relative 1e-8", "tests/test_extending.py::test_drag_demo_reaches_terminal_speed",
          "Fall speed against the exact `v_T (1 - exp(-t / tau))`."),
    Entry("capstan.py",
          "tension ratio of a rope sliding over a fixed drum (wrap pi, `mu = 0.3`) against "
          "`exp(mu pi)`, and the tension along the arc against `T1 exp(mu phi)`",
          "1 %", "tests/test_contact.py::test_capstan_slides_at_exp_mu_theta",
          "The rope on the drum with the drum's force on each element (arrows: normal and "
          "friction), and the tension along the arc."),
    Entry("esail_tangle.py",
          "penetration where tether 1 of a four-tether sail is pressed across tether 2 "
          "(the contact over all the tethers, each element's own tangent), against the "
          "stated tolerance `1e-2 d`",
          "< 1e-4 m", "tests/test_esail_tangle.py::test_tether_stops_on_its_neighbour",
          "A small sail whose tether 1 is pressed across tether 2: the contact force on "
          "both (arrows); the contacts in time; the closest approach of the baseline "
          "sail's tethers with one tether's voltage off and the spin halved (no contact)."),
    Entry("kapitza.py",
          "largest tilt of the rod with the pivot amplitude 5 % above the Floquet threshold "
          "(and 5 % below it: > 1 rad; the threshold against Kapitza's estimate: relative "
          "5e-3)",
          "< 0.15 rad", "tests/test_extending.py::test_kapitza_demo_threshold_both_sides",
          "Tilt from the upward vertical, 5 % above and 5 % below the threshold amplitude."),
    Entry("hanging_chain.py",
          "largest distance of the free end to the rigid-link chain, relative to the length, "
          "4 rods, 0.3 s (and to RK4 with half the step: < 1e-8)",
          "< 2e-5", "tests/test_rodchain.py::test_demo_runs_reduced",
          "The eleven rods every 0.05 s of the first second, released from horizontal."),
    Entry("esail_baseline.py",
          "angle of the thrust from the Sun line at the sailing angle `alpha = 10 deg`, at "
          "every saved step of three spin periods: about `alpha / 2`",
          "5 deg +- 0.1 deg",
          "tests/test_esail_baseline.py::test_tilted_thrust_drops_and_turns_by_about_half_alpha",
          "Thrust angle over three spin periods with the tolerance band, and the coning "
          "angle of the twelve tethers (`runs/esail`)."),
    Entry("spinning_hub.toml",
          "the tip position of `tether1` in `summary.json` against the stored results (run "
          "directory at 2 elements, 10 steps, 3 saved)",
          "`numpy.allclose`", "tests/test_cli.py::test_toml_scene_run_directory",
          "The two tethers and their remote units seen along the spin axis, every 0.5 s "
          "of the 5 s run."),
    Entry("mooring_current.py",
          "upstream end tension after 30 s of the transient against the static solve, 8 "
          "elements",
          "relative 1e-4", "tests/test_drag.py::test_demo_transient_settles_on_the_static_shape",
          "A 1 m/s current switched on: shapes every 2 s and the end tensions against the "
          "equilibrium equations."),
    Entry("mooring_line.toml",
          "end tensions and sag against `demos/mooring_current.py`, 20 elements",
          "relative 1e-6", "tests/test_drag.py::test_scene_file_mooring_line",
          "The 100 m line built straight and settled in the current."),
    Entry("esail_sweep.py",
          "mean thrust magnitude at `alpha = 0`, 20 kV (runs of 7.9 s, one element per "
          "tether, on a `LocalCluster` of two processes) against the Sun-facing "
          "`12 x 10 km x f(20 kV)`",
          "relative 1e-3", "tests/test_sweep.py::test_demo_esail_sweep",
          "Mean thrust magnitude and thrust angle against the sailing angle at 10 and 20 kV: "
          "14 runs of one spin period, one Dask task each (`runs/esail_sweep`)."),
    Entry("esail_steady.py",
          "mean coning angle of a run started from the steady state against the steady "
          "angle, and its largest deviation (integrator noise), 3 elements, one period",
          "relative 1e-5", "tests/test_steady.py::test_esail_steady_demo",
          "Coning angle over two spin periods from the steady state and from the usual "
          "start (the sail at rest in the stress-free configuration)."),
    Entry("esail_orbit.py",
          "centre of mass against a point mass propagated under the run's recorded thrust "
          "(DOP853), 72 minutes, 2 elements per tether",
          "1e-5 of the departure", "tests/test_demos.py::test_esail_orbit_demo",
          "A week around the Sun (2 elements per tether, 1 s steps): departure from the "
          "Keplerian orbit against the point mass, spin rate and sailing angle."),
    Entry("esail_thrust_vectoring.py",
          "thrust angle of the on-off sail (arcs of +-20 deg) at 10 deg against the rigid "
          "flat-sail model, 12 tethers, 2 elements each",
          "1e-3", "tests/test_demos.py::test_esail_thrust_vectoring_demo",
          "Thrust angle from the wind and thrust against the sailing angle: constant "
          "voltage leans the thrust by about half the sailing angle, a smooth `cos^2` "
          "modulation by three quarters, the on-off modulation of Toivanen, Janhunen and "
          "Envall (2015) by nearly all of it (crosses: the rigid flat sail)."),
    Entry("esail_rig.py",
          "least distance of neighbouring remote units over one spin period of on-off "
          "modulation (neighbours in antiphase) over the nominal spacing, with the ring "
          "of auxiliary tethers, 6 tethers of 2 elements",
          ">= 0.5", "tests/test_esail_rig.py::"
          "test_the_ring_keeps_the_units_apart_under_modulation",
          "The rig (24 tethers, remote units, the ring) in its steady spin facing the "
          "wind, and the least spacing of neighbouring units over a spin period of on-off "
          "modulation: the ring keeps it, without the ring units nearly collide."),
    Entry("esail_attitude_hold.py",
          "largest departure of the sailing angle from the commanded 30 deg over a tenth "
          "of a day, controlled against free",
          "< 0.5 of the free drift", "tests/test_demos.py::test_esail_attitude_hold_demo",
          "Five days around the Sun at a commanded 30 deg: the free sail's angle drifts "
          "with the orbit's turn, the phase-synchronous voltage modulation holds it within "
          "0.4 deg; spin rate of both against the rigid flat-sail drift."),
    Entry("esail_spin_control.py",
          "spin-rate drift of the 4-tether sail held at +-30 deg over 10000 s, free "
          "(sign and rate against the rigid flat sail's `Omega tan(alpha)`) and held by "
          "the remote units' thrusters",
          "sign, 20 %; held within 1 %",
          "tests/test_spin_control.py::test_controller_holds_the_spin_within_one_percent",
          "A day around the Sun at a held sailing angle of 30 deg: the free spin rises "
          "spiralling outward and falls inward (dotted: the rigid flat sail's "
          "+-Omega tan(alpha)); the remote units' thrusters hold it on its target."),
    Entry("tss_deployment_control.py",
          "in-plane libration and length error of the subsatellite deployed from 10 m to "
          "10 km in six orbits under Rupp's tension law (20 elements, sampled every 10 s)",
          "< 5 deg and 1 %", "tests/test_tss_deployment.py::"
          "test_rupps_law_settles_the_deployment_and_a_brake_does_not",
          "Length, rate and libration against orbits: Rupp's law follows the exponential "
          "command and settles the Coriolis swing (0.002 deg, 0.4 % short of 10 km); a "
          "constant brake lets the deployment run away 8 deg behind the vertical."),
    Entry("slack_catenary.py",
          "largest position error of the catenary found from the straight 12 m start, "
          "against the elastic catenary, 16 elements",
          "< 2e-5 of the span", "tests/test_slack_statics.py::test_demo_slack_catenary",
          "The cable hung between points 10 m apart, and the convergence of its errors."),
    Entry("spinning_hub_steady.toml",
          "tether tension against the rotating string anchored at the hub rim, and the tip "
          "radius during a run started from the steady state",
          "relative 1e-6 and 1e-7",
          "tests/test_steady.py::test_spinning_hub_scene_starts_steady",
          "Tip radius over 0.2 s from the steady state and from the stress-free start."),
    Entry("spinning_tether_steady.toml",
          "root tension in `summary.json` against the rotating extensible string",
          "relative 1e-6",
          "tests/test_steady.py::test_steady_analysis_scene_on_the_command_line",
          "Axial force along the spinning tether: `analysis = \"steady\"` and the "
          "rotating string."),
    Entry("tether_lowering.toml",
          "depth of the end mass after the tether is lowered from 10 m to 30 m",
          "30 m, relative 1e-3", "tests/test_deploy.py::test_scene_file_lowers_a_tether",
          "Depth of the end mass and tension below the reel against the weight hanging "
          "from it (started stress-free: the end mass bounces on the tether first)."),
    Entry("tether_retrieval.py",
          "growth of the swing amplitude while the reel pulls the tether in from 10 m to 5 m "
          "in 30 s, against the variable-length pendulum",
          "relative 2e-3",
          "tests/test_deploy.py::test_retrieval_demo_follows_the_variable_length_pendulum",
          "Swing angle while retrieving from 10 m to 2.5 m: the cable model on the "
          "pendulum's curve."),
    Entry("hub_deployment.py",
          "largest drift of the angular momentum about the spin axis, four tethers deployed "
          "from 10 m to 20 m in 20 s",
          "< 1e-3",
          "tests/test_deploy.py::test_hub_deployment_demo_conserves_angular_momentum",
          "Spin rate of the hub and rotation rate of the fan of tethers while they are "
          "deployed from 10 m to 50 m (the animation is on the deployment page)."),
    Entry("esail_deployment.py",
          "the sail's spin over the last turn after deploying four tethers from 300 m to "
          "500 m under the solar wind, against `H0 / I` of the deployed sail (with the "
          "final `H`: 1e-4)",
          "relative 1e-3",
          "tests/test_esail_deployment.py::"
          "test_spin_after_deployment_is_the_angular_momentum_over_the_deployed_inertia",
          "Spin rates of the hub and the remote units against `H0 / I(l)`, and the thrust "
          "against straight tethers, while four tethers deploy from 300 m to 1 km (the "
          "animation is on the deployment page)."),
    Entry("reel_brake.toml",
          "free length after 1 s of a tether unwinding under gravity from a braked reel, "
          "against the closed system's equation of the drum, its content and the hanging "
          "part",
          "5.6875 m, relative 1e-5", "tests/test_reel.py::test_scene_file_with_a_braked_reel",
          "Free length and tension below the reel: the cable model on the closed system's "
          "curve; started stress-free, the tension rings at the axial frequency (about "
          "80 Hz) around the weight less the force accelerating the hanging part."),
    Entry("reel_spin_rate.py",
          "settled spin rate after two reels on a spinning hub paid out 10 m -> 30 m of "
          "tether, against the rate at which the deployed, stretched configuration carries "
          "the run's angular momentum",
          "relative 1e-6",
          "tests/test_reel.py::test_settled_spin_rate_is_the_angular_momentum_prediction",
          "Hub spin rate and free length while the reels pay out 10 m -> 1 km; dashed: the "
          "angular-momentum prediction for the deployed configuration."),
    Entry("falling_chain.toml",
          "total energy at `t = 0` (the paper's Sect. 5.2)",
          "-62.87 J +- 0.01 J",
          "tests/test_rodchain_io.py::test_example_scene_file_is_the_papers_energy_experiment",
          "The twenty rods every 0.5 s, and the energies: their total stays constant."),
    Entry("tss_libration.py",
          "pitch libration frequency of the 20 km tethered satellite system in a 400 km "
          "orbit (0.05 rad pitch, 0.03 rad roll, 4 elements, 100 steps per period) against "
          "`sqrt(3) n (1 - (2 theta_0)^2 / 16)`; the roll against `2 n`: 1e-3",
          "relative 2e-3", "tests/test_orbit_scenes.py::test_tss_libration_demo",
          "Pitch and roll over three pitch periods against the rigid dumbbell's small "
          "librations at `sqrt(3) n` and `2 n` (dotted: their periods)."),
    Entry("ed_tether_deorbit.py",
          "altitude drop of the 5 km bare tape (OML current from IRI in IGRF) over 0.07 "
          "days against Gauss's equation `da/dt = 2 a^2 (V . F) / (mu m)` integrated with "
          "the Lorentz force the run reports",
          "relative 2e-2",
          "tests/test_ed_deorbit.py::test_demo_follows_gauss_equation",
          "Altitude of the centre of mass's osculating orbit over a day, the "
          "cathode's current, the motional power and the EMF (IGRF, IRI, MSIS drag)."),
    Entry("plasma_brake.py",
          "altitude drop of the 260 kg object under the 5 km plasma brake at -1 kV (IRI at "
          "60 s knots) over 0.05 days against Gauss's equation `da/dt = 2 a^2 (V . F) / "
          "(mu m)` integrated with the brake's force the run reports",
          "relative 2e-2", "tests/test_plasma_brake.py::test_demo_follows_gauss_equation",
          "Altitude of the centre of mass's osculating orbit over two days and the braking "
          "force against Janhunen's 0.43 mN (IRI, F10.7 = 150, from 800 km)."),
    Entry("tape_tether.py",
          "period of the end-to-end twist of the 5 km aluminium tape in a 400 km orbit (8 "
          "elements, 1500 s) against the free-free torsional period `2 L / c`, `c = "
          "sqrt(GJ / rho I_p)`; its pitch libration the round tether's of equal mass: "
          "< 1e-4 rad",
          "relative 1e-2", "tests/test_rod_scenes.py::test_tape_tether_demo",
          "Spin-up on a hub, seen from above at 1.6 s: the flat tape (blue) bends edgewise "
          "and lags little; the tape pitched by 45 degrees (orange) twists its soft axis "
          "into the lag, lags as far as the round tether (dashed) and leaves the spin "
          "plane; right: the twist of the tape in orbit swinging at `2 L / c`."),
)


# --- the page ---------------------------------------------------------------------------
def docstring(path):
    """The module docstring of a demo; for a scene file, its ``title`` then its leading
    comment block."""
    path = Path(path)
    text = path.read_text()
    if path.suffix == ".py":
        return ast.get_docstring(ast.parse(text)) or ""
    lines = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[2:] if line.startswith("# ") else line[1:])
    title = tomllib.loads(text).get("title", path.name)
    return title + "\n\n" + "\n".join(lines).strip()


def markdown_body(text):
    """Docstring text as Markdown: numpydoc section underlines become bold paragraphs
    (not headings of the page), the rest is kept (indented blocks are code)."""
    lines = text.splitlines()
    out = []
    for k, line in enumerate(lines):
        nxt = lines[k + 1] if k + 1 < len(lines) else ""
        if line.strip() and set(nxt.strip()) == {"-"} and len(nxt.strip()) >= 3:
            out.append(f"**{line.strip()}**")
        elif set(line.strip()) == {"-"} and k > 0 and lines[k - 1].strip():
            continue
        else:
            out.append(line)
    return "\n".join(out)


def entry_markdown(entry, demos=DEMOS):
    """The section of one demo."""
    text = docstring(Path(demos) / entry.demo)
    summary, _, body = text.partition("\n")
    parts = [f"## {summary.strip().rstrip('.')}", "",
             f"`demos/{entry.demo}`", "",
             f"![{entry.name}]({entry.picture})", "",
             f"*{entry.caption}*", "",
             "| checks | tolerance | test |", "| --- | --- | --- |",
             f"| {entry.check} | {entry.tolerance} | `{entry.test}` |", "",
             "```bash", entry.command, "```", "",
             markdown_body(body.strip()), ""]
    return "\n".join(parts)


def page(entries=ENTRIES, demos=DEMOS):
    """The whole gallery page (Markdown)."""
    head = ["# Gallery", "",
            "Each file of `demos/` is a short, runnable script (or scene file) whose docstring "
            "states the physics; its test imports it at reduced size and checks one number "
            "against an independent reference (scikit-fem's habit).  Below: the demo's "
            "docstring, a picture drawn from a run of it (a script draws its own, with its "
            "`gallery_figure(path)`), the number its test checks with "
            "the tolerance, and the command that runs it.  The page is generated when the "
            "docs are built (`scripts/gallery.py`, an MkDocs hook) from the demos' "
            "docstrings; the pictures are redrawn with `.venv/bin/python scripts/gallery.py`.",
            "",
            "| demo | checks | tolerance |", "| --- | --- | --- |"]
    for e in entries:
        title = docstring(Path(demos) / e.demo).partition("\n")[0].strip().rstrip(".")
        anchor = _slug(title)
        head.append(f"| [`{e.demo}`](#{anchor}) | {e.check} | {e.tolerance} |")
    head.append("")
    return "\n".join(head + [entry_markdown(e, demos) for e in entries])


def _slug(title):
    """The anchor MkDocs' ``toc`` extension gives a heading."""
    from markdown.extensions.toc import slugify

    plain = re.sub(r"`", "", title)
    return slugify(plain, "-")


def on_files(files, config):
    """MkDocs hook: add the generated ``gallery.md`` to the documentation files."""
    from mkdocs.structure.files import File

    files.append(File.generated(config, "gallery.md", content=page()))
    return files


# --- the pictures -------------------------------------------------------------------------
# A demo script draws its own picture: its ``gallery_figure(path)`` runs it and writes the
# PNG.  A scene file holds no code, so its picture is drawn here (``draw_<name>``).

#: Keywords of a demo's ``gallery_figure`` beyond the path (pictures of other pages).
DEMO_OPTIONS = {"tss_libration": {"render": ROOT / "docs" / "figures" / "tss_lvlh.png"}}


def draw_demo(name):
    """Run ``demos/NAME.py``'s ``gallery_figure`` into the picture; check its size."""
    _load_demo(name).gallery_figure(_path(name), **DEMO_OPTIONS.get(name, {}))
    _written(name)


def _load_demo(name):
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"gallery_{name}", DEMOS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _figure(ncols=1, width=7.0, height=3.0):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, ncols, figsize=(width, height), layout="constrained")
    return fig, axes


def _path(name):
    path = ROOT / "docs" / FIGURES / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def _save(fig, name):
    import matplotlib.pyplot as plt

    fig.savefig(_path(name), dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)
    _written(name)


def _written(name):
    """Report the size of the picture ``name``; refuse one that is too large."""
    path = _path(name)
    size = path.stat().st_size
    print(f"{path.relative_to(ROOT)}: {size / 1e3:.0f} kB")
    if size > MAX_BYTES:
        raise RuntimeError(f"{path} is {size} bytes, more than {MAX_BYTES}")


# --- the scene files' pictures ----------------------------------------------------------
def draw_spinning_hub():
    import numpy as np

    import skfem_cable as sc
    from skfem_cable import scene_file

    spec = scene_file.load(DEMOS / "spinning_hub.toml")
    r = sc.simulate(spec.system, initial=spec.initial, **spec.solver)
    cables = spec.system.cables()
    fig, ax = _figure(width=4.6, height=4.4)
    s_of = {c.name: np.linspace(0, c.length, 41) for c in cables}
    times = np.arange(0.0, r.t[-1] + 1e-9, 0.5)
    for k, t in enumerate(times):
        i = int(np.argmin(abs(r.t - t)))
        for j, c in enumerate(cables):
            p = r.position(c, s_of[c.name])[i]
            ax.plot(p[:, 1], p[:, 2], color=f"C{j}", alpha=0.3 + 0.7 * k / len(times), lw=1)
            ax.plot(p[-1, 1], p[-1, 2], "o", color=f"C{j}", ms=3)
    phi = np.linspace(0, 2 * np.pi, 60)
    ax.fill(0.5 * np.cos(phi), 0.5 * np.sin(phi), color="0.6")
    ax.set_aspect("equal")
    ax.set_xlabel("y [m]")
    ax.set_ylabel("z [m]")
    ax.set_title("spinning hub, 2 tethers, every 0.5 s", fontsize=10)
    _save(fig, "spinning_hub")


def draw_falling_chain():
    import numpy as np

    from skfem_cable import scene_file

    spec = scene_file.load(DEMOS / "falling_chain.toml")
    res = spec.chain.simulate(*spec.initial, spec.solver["t_end"], spec.solver["step"],
                              output_every=10, **spec.loads)
    fig, (a, b) = _figure(2, width=8.5, height=3.4)
    frames = np.searchsorted(res.t, np.arange(0.0, res.t[-1] + 1e-9, 0.5) - 1e-9)
    for k in frames:
        j = res.joints[k]
        a.plot(j[:, 0], j[:, 1], color="C0", lw=1, alpha=0.2 + 0.8 * res.t[k] / res.t[-1])
    a.plot(0, 0, "ko")
    a.set_aspect("equal")
    a.set_xlabel("x [m]")
    a.set_ylabel("y [m]")
    a.set_title("20 soft rods, every 0.5 s to 5 s", fontsize=10)
    E = res.energy
    for key in ("kinetic", "elastic", "potential", "total"):
        b.plot(res.t, E[key], label=key)
    b.set_xlabel("t [s]")
    b.set_ylabel("J")
    b.legend(fontsize=8)
    b.set_title(f"energies; total at t = 0: {E['total'][0]:.2f} J", fontsize=10)
    _save(fig, "falling_chain")


def draw_spinning_hub_steady():
    import numpy as np

    import skfem_cable as sc
    from skfem_cable import scene_file

    path = DEMOS / "spinning_hub_steady.toml"
    spec = scene_file.load(path)
    omega = tomllib.loads(path.read_text())["initial"]["angular_velocity"]
    fig, ax = _figure(width=6.0, height=3.0)
    rest = sc.State(spec.system, spec.system.q0,
                    v=spec.system.rigid_motion_velocity(spec.system.q0, omega))
    for label, initial in (("steady state", spec.initial), ("stress-free start", rest)):
        r = sc.simulate(spec.system, t_end=1.0, dt=5e-3, rho_inf=0.8, initial=initial)
        cable = spec.system.cables()[0]
        radius = np.linalg.norm(r.position(cable, cable.length)[:, 1:], axis=1)
        ax.plot(r.t, radius, label=label)
    ax.set(xlabel="t [s]", ylabel="tip radius [m]")
    ax.legend(fontsize=8)
    _save(fig, "spinning_hub_steady")


def draw_spinning_tether_steady():
    import numpy as np

    from skfem_cable import scene_file
    from skfem_cable.analysis.analytic import rotating_string
    from skfem_cable.solvers.steady import solve_steady

    spec = scene_file.load(DEMOS / "spinning_tether_steady.toml")
    state = solve_steady(spec.system, **spec.solver)
    cable = spec.system.cables()[0]
    s = np.linspace(0.0, cable.length, 101)
    omega = np.linalg.norm(spec.solver["omega"])
    mass = spec.system.point_masses[0].mass
    _, T = rotating_string(s, cable.length, cable.section.EA, cable.section.mass_per_length,
                           mass, omega)
    fig, ax = _figure(width=6.0, height=3.0)
    ax.plot(s, T, color="0.6", lw=3, label="rotating extensible string")
    ax.plot(s, state.tension(cable, s), "C0", lw=1, label="solve_steady")
    ax.set(xlabel="s [m]", ylabel="axial force [N]")
    ax.legend(fontsize=8)
    _save(fig, "spinning_tether_steady")


def draw_tether_lowering():
    import skfem_cable as sc
    from skfem_cable import scene_file

    spec = scene_file.load(DEMOS / "tether_lowering.toml")
    r = sc.simulate(spec.system, initial=spec.initial, **spec.solver)
    cable = spec.system.bodies[0]
    mu = cable.section.mass_per_length
    ell = [spec.system.deployment(cable).state(t)[0] for t in r.t]
    weight = [(mu * x + spec.system.point_masses[0].mass) * 9.81 for x in ell]
    fig, (ax, bx) = _figure(ncols=2, width=8.0, height=3.0)
    ax.plot(r.t, -r.position(cable, cable.length)[:, 1], label="end mass")
    ax.plot(r.t, ell, "k:", lw=1, label="free length")
    ax.set(xlabel="t [s]", ylabel="depth [m]")
    ax.legend(fontsize=8)
    bx.plot(r.t, r.tension(cable, 0.0), label="tension below the reel")
    bx.plot(r.t, weight, "k:", lw=1, label="weight hanging from it")
    bx.set(xlabel="t [s]", ylabel="force [N]")
    bx.legend(fontsize=8)
    _save(fig, "tether_lowering")


def draw_mooring_line():
    import numpy as np

    import skfem_cable as sc
    from skfem_cable import scene_file

    spec = scene_file.load(DEMOS / "mooring_line.toml")
    state = sc.solve_static(spec.system)
    cable = spec.system.bodies[0]
    r = state.position(cable, np.linspace(0.0, cable.length, 201))
    fig, ax = _figure(width=5.0, height=2.8)
    ax.plot([0, cable.length], [0, 0], "C7:", label="built straight (100 m)")
    ax.plot(r[:, 0], r[:, 2], "C0-", label="settled in the current")
    ax.annotate("1 m/s", xy=(70, -8), xytext=(52, -8), arrowprops={"arrowstyle": "->"},
                va="center", fontsize=8)
    ax.set(xlabel="x [m]", ylabel="z [m]", aspect="equal")
    ax.legend(fontsize=8, loc="lower left")
    _save(fig, "mooring_line")


def draw_reel_brake():
    from scipy.integrate import solve_ivp

    import skfem_cable as sc
    from skfem_cable import scene_file

    spec = scene_file.load(DEMOS / "reel_brake.toml")
    r = sc.simulate(spec.system, initial=spec.initial, **{**spec.solver, "every": 1})
    tether, reel = spec.system.bodies
    ell = r.q[:, spec.system.dofs(reel)[0]]
    mu, J, R, C, m, c, g = tether.section.mass_per_length, 0.02, 0.1, 30.0, 0.5, 0.3, 9.81

    def rhs(t, y):
        return [y[1], ((mu * y[0] + m) * g - c * y[1] / R) / (J / R**2 + mu * C + m)]

    exact = solve_ivp(rhs, (0.0, 1.0), [5.0, 0.0], rtol=1e-12, atol=1e-12,
                      dense_output=True).sol(r.t)[0]
    fig, (ax, bx) = _figure(ncols=2, width=7.5, height=3.0)
    ax.plot(r.t, exact, color="0.6", lw=3, label="closed system")
    ax.plot(r.t, ell, "C0", lw=1, label="cable model")
    ax.set(xlabel="t [s]", ylabel="free length [m]")
    ax.legend(fontsize=8)
    bx.plot(r.t, r.tension(tether, 0.0), "C1")
    bx.set(xlabel="t [s]", ylabel="tension below the reel [N]")
    fig.suptitle(f"Braked reel: l(1 s) = {ell[-1]:.5f} m (closed system {exact[-1]:.5f} m)",
                 fontsize=10)
    _save(fig, "reel_brake")


#: The function drawing each entry's picture.
DRAW = {e.name: partial(draw_demo, e.name) if e.demo.endswith(".py")
        else globals()[f"draw_{e.name}"] for e in ENTRIES}


if __name__ == "__main__":
    for name in sys.argv[1:] or list(DRAW):
        DRAW[name]()
