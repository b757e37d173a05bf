"""An E-sail whose control fails: tether-tether contact over all the sail's tethers
(issue 49, item 5; ``docs/contact.md``, "Many lines: a sail's tethers").

1. The baseline sail (12 tethers of 10 km, ``esail.BaselineConfig``, 5 elements each)
   with tether 1's voltage switched off and the spin rate halved, for two of its spin
   periods (1.7 h), with the contact over all its tethers
   (``system.contact(scene.tethers)``: one broad phase, the pairs next to the hub left
   out, each element's own tangent with the coupling of the pairs in contact added back
   by the compiled step, so that the bordered band LU still solves the sail).
   No tether touches another: the centrifugal ratio is still 14.8 (59 at the nominal
   spin), and the tethers' closest approach, recorded at every saved step, stays above
   about 600 m.
2. A small sail that does touch (``esail_tangle.crossing_sail``: 12 tethers of 1 m, the
   capstan's rope, on a hub): tether 1 is pressed across tether 2.  The contact is
   found, located (which tethers, where along each) and held: the penetration stays
   below the stated tolerance, the forces are equal and opposite.

Run ``python demos/esail_tangle.py`` (6 s of CPU with the kernels compiled, about 30 s
with compiling);
``tests/test_esail_tangle.py`` checks the small sail (with 4 tethers).
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes.esail_tangle import closest_approach, crossing_sail, failed_sail

#: The failed sail's run: spin periods, step (s) and saved steps.
PERIODS, DT, EVERY = 2.0, 2.0, 25
#: The small sail's run (s), step (s) and saved steps.
T_SMALL, DT_SMALL, EVERY_SMALL = 0.45, 1e-4, 50


def failed(periods=PERIODS):
    """The baseline sail whose control failed (``failed_sail``) run for ``periods`` of
    its spin: ``(scene, result, approach)``, ``approach`` the closest approach
    ``(distance, i, j)`` at every saved step (``closest_approach``)."""
    scene = failed_sail()
    system = scene.system
    result = sc.simulate(system, periods * scene.config.spin_period, DT,
                         initial=scene.initial, rho_inf=0.25, every=EVERY)
    approach = [closest_approach(system, scene.tethers, q) for q in result.q]
    return scene, result, approach


def small(n_tethers=12):
    """The small sail of ``n_tethers`` with tether 1 pressed across tether 2
    (``crossing_sail``): ``(system, tethers, contact, result, history)``, ``history`` the
    contacts (``contact.contacts``) at every saved step."""
    system, hub, tethers, contact = crossing_sail(n_tethers)
    result = sc.simulate(system, T_SMALL, DT_SMALL, every=EVERY_SMALL)
    history = [contact.contacts(system, result.state(i).q, result.state(i).v)
               for i in range(len(result))]
    return system, tethers, contact, result, history


def main():
    """Run both sails and print what they report (and the run time)."""
    start = time.process_time()
    scene, result, approach = failed()
    distance, i, j = min(approach)
    print(f"failed sail: {len(result)} saved steps over {result.t[-1] / 3600:.2f} h; "
          f"contacts {int(max(result.outputs['contact_lines_contacts']))}; closest "
          f"approach {distance:.0f} m (tethers {i + 1} and {j + 1})")
    system, tethers, contact, result, history = small()
    last = history[-1]
    print(f"small sail: contacts at the end {len(last['normal'])}")
    for (a, b), (sa, sb), normal in zip(last["lines"], last["arc"], last["normal"]):
        print(f"  tether {a + 1} at {sa:.3f} m on tether {b + 1} at {sb:.3f} m: "
              f"{normal:.1f} N")
    print(f"  largest penetration {max(h['max_penetration'] for h in history):.2e} m "
          f"(stated tolerance {contact.tolerance * contact.sum_radii:.0e} m)")
    print(f"run time {time.process_time() - start:.1f} s of CPU")


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the small sail at the
    end, its contact force drawn as arrows on both tethers; its contacts in time; the
    failed sail's closest approach in time."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    system, tethers, contact, result, history = small()
    scene, failed_result, approach = failed()
    fig = plt.figure(figsize=(10.0, 3.4), layout="constrained")
    ax = fig.add_subplot(1, 3, 1)
    q = result.q[-1]
    ends = tethers[1].line_points(system).at(q)[0].reshape(-1, 3)[[0, -1]]
    along = np.array([0.0, *(ends[1] - ends[0])[1:]])
    along /= np.linalg.norm(along)                             # tether 2's direction
    for tether, style in zip(tethers[:2], ("k-", "0.5")):
        x = tether.line_points(system).at(q)[0].reshape(-1, 3)
        ax.plot(x @ along, 1e3 * x[:, 0], style, lw=1.2, label=tether.name)
    last = history[-1]
    at = np.vstack([last["first"], last["second"]])
    n = last["first"] - last["second"]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    push = np.vstack([n, -n]) * np.concatenate([last["normal"]] * 2)[:, None]
    scale = 6.0 / np.abs(push[:, 0]).max()                     # mm per N
    ax.quiver(at @ along, 1e3 * at[:, 0], push @ along, scale * push[:, 0],
              angles="xy", scale_units="xy", scale=1.0, color="tab:red", width=0.008)
    ax.set_xlabel("along tether 2 [m]")
    ax.set_ylabel("x [mm]")
    ax.set_title("small sail, side view along tether 2:\ncontact forces (arrows)", fontsize=9)
    ax.legend(fontsize=8)
    bx = fig.add_subplot(1, 3, 2)
    bx.plot(result.t, [h["normal"].sum() for h in history], "k-", lw=1)
    bx.set_xlabel("t [s]")
    bx.set_ylabel("total normal force [N]")
    bx.set_title("small sail: contacts in time", fontsize=9)
    twin = bx.twinx()
    twin.step(result.t, [len(h["normal"]) for h in history], "tab:blue", lw=0.8)
    twin.set_ylabel("contacts", color="tab:blue")
    twin.set_yticks(range(max(len(h["normal"]) for h in history) + 1))
    cx = fig.add_subplot(1, 3, 3)
    cx.plot(failed_result.t / 3600, [a[0] for a in approach], "k-", lw=1)
    cx.axhline(contact_distance(scene), color="tab:red", lw=0.8, label="touching")
    cx.set_yscale("log")
    cx.set_xlabel("t [h]")
    cx.set_ylabel("closest approach [m]")
    cx.set_title("failed 12-tether sail: no contact", fontsize=9)
    cx.legend(fontsize=8)
    fig.savefig(path, dpi=80)
    plt.close(fig)


def contact_distance(scene):
    """The distance (m) of two tethers' centrelines at touch in ``scene``."""
    return scene.system.loads[-1].sum_radii


if __name__ == "__main__":
    main()
