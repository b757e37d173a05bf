"""Power spectral densities of uniformly sampled signals (Welch's method): the one spectrum
function of the package, drawn by ``plot.psd`` and used by the E-sail's ``esail.psd``.

Numbers only (numpy, and scipy on first use): no matplotlib, so that physics modules can
import it.
"""

import numpy as np


def _uniform_samples(t, x):
    """``t``, ``x`` and the step, without a shortened last step; raises ``ValueError``
    unless uniformly spaced."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dt = np.diff(t)
    if len(dt) > 1 and abs(dt[-1] - dt[0]) > 1e-6 * dt[0]:
        # a run's last saved step may follow a shortened final step: leave it out
        t, x, dt = t[:-1], x[:-1], dt[:-1]
    if len(t) < 8 or np.ptp(dt) > 1e-6 * dt.mean():
        raise ValueError("the PSD needs at least 8 uniformly spaced samples "
                         "(save steps with a constant stride)")
    return t, x, float(dt.mean())


def welch_plan(n, dt, segments=4, f_min=None, cycles=4):
    """Segment and FFT lengths (samples) of ``spectrum`` for ``n`` samples ``dt`` apart.

    With ``f_min`` (Hz, the lowest frequency to resolve, e.g. a spin frequency): segments
    of ``cycles`` periods of ``f_min`` (bins ``f_min / cycles`` wide), half-overlapping
    and averaged as often as the run allows; a shorter run is one segment zero-padded to
    that length (the bins are as fine, but peaks closer than about ``2 / (n dt)``, the
    Hann window's main lobe, merge).  Otherwise ``segments`` half-overlapping segments.

    Returns
    -------
    nperseg, nfft : int
    """
    if f_min is not None:
        nfft = int(np.ceil(cycles / (f_min * dt)))
        return min(n, nfft), nfft
    nperseg = min(n, max(8, 2 * n // (segments + 1)))
    return nperseg, nperseg


def spectrum(t, x, segments=4, f_min=None, cycles=4):
    """One-sided power spectral density of a uniformly sampled signal (Welch's method,
    Hann window, half-overlapping segments of ``welch_plan``, mean removed).

    Parameters
    ----------
    t : ndarray (nt,)
        Uniform sample times (a shortened last step, as a run may end with, is left out).
    x : ndarray (nt,) or (nt, ...)
        Samples, time along the first axis (several signals at once: one per column).
    segments, f_min, cycles
        As in ``welch_plan``.

    Returns
    -------
    f : ndarray
        Frequencies (Hz).
    psd : ndarray
        Densities (units^2 / Hz), frequency along the first axis.
    """
    from scipy.signal import welch

    t, x, dt = _uniform_samples(t, x)
    nperseg, nfft = welch_plan(len(t), dt, segments, f_min, cycles)
    return welch(x, fs=1.0 / dt, nperseg=nperseg, nfft=nfft, detrend="constant", axis=0)


def welch_note(t, x, f_min=None):
    """What ``spectrum`` (with ``f_min``, else its default segments) averages, as text:
    segments, their length, the bin width and, for a zero-padded segment, the resolution
    the run allows."""
    t, _, dt = _uniform_samples(t, x)
    nperseg, nfft = welch_plan(len(t), dt, f_min=f_min)
    count = 1 + (len(t) - nperseg) // (nperseg - nperseg // 2)
    note = (f"Welch, Hann window: {count} segment{'s' if count > 1 else ''} of "
            f"{nperseg * dt:.4g} s; bins {1 / (nfft * dt):.3g} Hz")
    if nfft > nperseg:
        note += f"\nzero-padded: peaks closer than ~{2 / (nperseg * dt):.2g} Hz merge"
    return note
