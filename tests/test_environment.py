"""The near-Earth environment (``skfem_cable.environment``): the models against their
libraries called directly at the same place and time (ppigrf, pymsis, PyIRI), the IGRF
gradient against central differences, and the GCRS -> ITRS rotation against astropy."""

import datetime
import doctest
import importlib

import astropy.units as u
import numpy as np
import ppigrf
import PyIRI
import pymsis
import pytest
from astropy.coordinates import GCRS, ITRS, CartesianRepresentation, EarthLocation
from astropy.time import Time
from PyIRI import edp_update

import skfem_cable as sc

EPOCH = "2026-03-20T06:00:00"
T = 5400.0  # s after the epoch: the models are evaluated at EPOCH + 90 min
X = np.array([[4.1e6, -3.9e6, 4.0e6], [-6.2e6, 1.1e6, -2.4e6]])  # GCRS, m (~400-500 km)


def astropy_to_itrs(x, when):
    frame = GCRS(CartesianRepresentation(np.asarray(x).T * u.m), obstime=when)
    return frame.transform_to(ITRS(obstime=when)).cartesian.xyz.to_value(u.m).T


def astropy_to_gcrs(y, when):
    frame = ITRS(CartesianRepresentation(np.asarray(y).T * u.m), obstime=when)
    return frame.transform_to(GCRS(obstime=when)).cartesian.xyz.to_value(u.m).T


def geodetic_point_in_gcrs(lon, lat, height_km, when):
    where = EarthLocation.from_geodetic(lon * u.deg, lat * u.deg, height_km * u.km)
    return astropy_to_gcrs(where.get_itrs(obstime=when).cartesian.xyz.to_value(u.m), when)


def when():
    return Time(EPOCH, scale="utc") + T * u.s


@pytest.mark.parametrize("module", ["epoch", "igrf", "msis", "iri", "plasma", "oml"])
def test_docstring_examples_run(module):
    result = doctest.testmod(importlib.import_module(f"skfem_cable.environment.{module}"),
                             optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0


def test_epoch_accepts_datetime_time_string_and_epoch():
    start = datetime.datetime(2026, 3, 20, 6, 0, 0)
    for value in (start, Time(EPOCH), EPOCH, sc.Epoch(EPOCH)):
        assert sc.Epoch(value).datetime(T) == start + datetime.timedelta(seconds=T)
    with pytest.raises(ValueError, match="epoch"):
        sc.Epoch("not a date")


def test_rotation_is_orthonormal_and_matches_astropy():
    """``R`` orthonormal to 1e-14 with determinant 1; ``R x`` equals astropy's transform
    of the points within 1e-12 relative (the rotation is linear, as the transform)."""
    epoch = sc.Epoch(EPOCH)
    R = epoch.gcrs_to_itrs(T)
    assert np.abs(R @ R.T - np.eye(3)).max() < 1e-14
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
    error = np.abs(epoch.to_itrs(X, T) - astropy_to_itrs(X, when())).max() / 7e6
    print(f"GCRS -> ITRS against astropy: relative error {error:.1e}")
    assert error < 1e-12
    assert epoch.gcrs_to_itrs(T) is R  # cached per time
    axis = epoch.earth_rotation(T) / np.linalg.norm(epoch.earth_rotation(T))
    assert np.degrees(np.arccos(axis[2])) < 0.5  # the pole: precession since J2000


def test_igrf_equals_ppigrf_rotated_back():
    """The field at GCRS points equals ppigrf's geodetic (east, north, up) components at
    the same Earth-fixed place, rotated back by astropy, within 1e-4 relative."""
    B, _ = sc.environment.IGRF(EPOCH).field(X, T)
    y = astropy_to_itrs(X, when())
    where = EarthLocation.from_geocentric(*y.T, unit=u.m)
    lon, lat, h = (q.to_value(v) for q, v in zip(where.to_geodetic("WGS84"),
                                                  (u.deg, u.deg, u.km)))
    Be, Bn, Bu = (c.ravel() for c in ppigrf.igrf(lon, lat, h, when().to_datetime()))
    lam, phi = np.radians(lon), np.radians(lat)
    east = np.stack([-np.sin(lam), np.cos(lam), 0 * lam], -1)
    north = np.stack([-np.sin(phi) * np.cos(lam), -np.sin(phi) * np.sin(lam), np.cos(phi)], -1)
    up = np.stack([np.cos(phi) * np.cos(lam), np.cos(phi) * np.sin(lam), np.sin(phi)], -1)
    B_itrs = 1e-9 * (Be[:, None] * east + Bn[:, None] * north + Bu[:, None] * up)
    reference = astropy_to_gcrs(B_itrs, when())
    error = (np.linalg.norm(B - reference, axis=1) / np.linalg.norm(reference, axis=1)).max()
    print(f"IGRF against ppigrf: relative error {error:.1e}")
    assert error < 1e-4


def test_igrf_reads_its_coefficient_file_once_and_as_ppigrf_reads_it():
    """The memo of ppigrf's coefficient file (``igrf.ppigrf``): a second field call reads
    no file and gives the same field bit for bit; each call gets copies equal to a fresh
    read, so that an edit of one does not reach the next."""
    from ppigrf import ppigrf as module

    from skfem_cable.environment.igrf import ppigrf as memoized_ppigrf
    memoized_ppigrf()
    read = module.read_shc
    igrf = sc.environment.IGRF(EPOCH)
    first = igrf.field(X, T)
    misses = read.memoized.cache_info().misses
    for kept, again in zip(first, igrf.field(X, T)):
        assert np.array_equal(kept, again)
    assert read.memoized.cache_info().misses == misses
    g, h = read()
    g.iloc[0, 0] = np.nan
    for kept, fresh in zip(read(), read.__wrapped__()):
        assert kept.equals(fresh)


def test_igrf_gradient_against_central_differences():
    """``dB/dx`` against central differences of the field with a 1 km step in the GCRS
    axes (1e-5 of the gradient's norm), curl-free and divergence-free to 1e-7."""
    igrf = sc.environment.IGRF(EPOCH)
    _, dB = igrf.field(X, T)
    h = 1e3
    fd = np.stack([(igrf(X + h * e, T) - igrf(X - h * e, T)) / (2 * h) for e in np.eye(3)],
                  axis=-1)
    norm = np.linalg.norm(dB, axis=(1, 2))
    error = (np.linalg.norm(dB - fd, axis=(1, 2)) / norm).max()
    curl = (np.linalg.norm(dB - dB.transpose(0, 2, 1), axis=(1, 2)) / norm).max()
    divergence = (np.abs(np.trace(dB, axis1=1, axis2=2)) / norm).max()
    print(f"IGRF gradient: {error:.1e} against central differences, curl {curl:.1e}, "
          f"divergence {divergence:.1e}")
    assert error < 1e-5 and curl < 1e-7 and divergence < 1e-7


def test_msis_equals_pymsis_at_the_geodetic_point():
    """The density at the GCRS image of geodetic points equals pymsis's there within
    1e-6 relative."""
    msis = sc.environment.MSIS(EPOCH, f107=150.0, f107a=140.0, ap=7.0)
    points = [(-70.0, 35.0, 400.0), (120.0, -60.0, 300.0), (10.0, 5.0, 700.0)]
    date = np.datetime64(when().to_datetime(), "ns")
    for lon, lat, h in points:
        x = geodetic_point_in_gcrs(lon, lat, h, when())
        ours = msis.density(x, T)
        ref = pymsis.calculate(date, lon, lat, h, 150.0, 140.0, [[7.0] * 7])
        error = abs(ours / ref.ravel()[pymsis.Variable.MASS_DENSITY] - 1.0)
        print(f"MSIS at {lon, lat, h}: relative error {error:.1e}")
        assert error < 1e-6


def test_iri_density_as_pyiri_gives_it():
    """The electron density at the GCRS image of geodetic points (several heights in one
    call) equals PyIRI's ``IRI_density_1day`` at each within 1e-6 relative."""
    iri = sc.environment.IRI(EPOCH, f107=150.0)
    points = [(-70.0, 35.0, 400.0), (120.0, -20.0, 300.0), (10.0, 5.0, 700.0)]
    x = np.vstack([geodetic_point_in_gcrs(*p, when()) for p in points])
    ours = iri.density(x, T)
    moment = when().to_datetime()
    hours = moment.hour + moment.minute / 60 + moment.second / 3600
    for (lon, lat, h), n_e in zip(points, ours):
        *_, edp = edp_update.IRI_density_1day(
            moment.year, moment.month, moment.day, np.array([hours]), np.array([lon]),
            np.array([lat]), np.array([h]), 150.0, PyIRI.coeff_dir)
        error = abs(n_e / edp[0, 0, 0] - 1.0)
        print(f"IRI at {lon, lat, h}: {n_e:.4e} m^-3, relative error {error:.1e}")
        assert error < 1e-6


def test_iri_reads_a_months_coefficients_once_and_as_pyiri_reads_them():
    """The memo of PyIRI's coefficient files (``iri.pyiri``): a second density call in
    the same month reads no file, and the memoized arrays equal a fresh read, read-only."""
    from PyIRI import main_library

    from skfem_cable.environment.iri import pyiri
    pyiri()
    read = main_library.read_ccir_ursi_coeff
    iri = sc.environment.IRI(EPOCH, f107=150.0)
    first = iri.density(X, T)
    misses = read.memoized.cache_info().misses
    assert np.array_equal(iri.density(X, T), first)
    assert read.memoized.cache_info().misses == misses
    month = when().to_datetime().month
    for kept, fresh in zip(read(month, PyIRI.coeff_dir), read.__wrapped__(month, PyIRI.coeff_dir)):
        assert np.array_equal(kept, fresh) and not kept.flags.writeable


def test_plasmas_co_rotate_and_check_their_arguments():
    iri = sc.environment.IRI(EPOCH, f107=150.0)
    v = iri.velocity(X, T)
    omega = iri.epoch.earth_rotation(T)
    assert np.allclose(v, np.cross(omega, X), rtol=1e-15)
    assert np.linalg.norm(omega) == pytest.approx(sc.space.constants.OMEGA_EARTH)
    plasma = sc.environment.UniformPlasma(1e11, temperature=2000.0, velocity=(1.0, 2.0, 3.0))
    assert plasma.velocity(X).shape == X.shape and plasma.temperature(X).shape == (2,)
    with pytest.raises(ValueError, match="density"):
        sc.environment.UniformPlasma(-1.0)
    with pytest.raises(ValueError, match="f107"):
        sc.environment.MSIS(EPOCH, f107=-5.0, f107a=100.0, ap=4.0)
