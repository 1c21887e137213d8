"""Signal analysis for results: dominant frequency, amplitude envelope, natural frequencies."""
from __future__ import annotations

import numpy as np


def spectrum(t: np.ndarray, y: np.ndarray, pad: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum of ``y`` (mean removed, Hann window, zero-padded ``pad`` times).

    ``t``: (n,) equally spaced times in s. Returns frequencies in Hz and amplitudes.
    """
    dt = float(np.mean(np.diff(t)))
    w = np.hanning(len(y))
    amp = np.abs(np.fft.rfft((y - np.mean(y)) * w, pad * len(y))) * 2 / w.sum()
    return np.fft.rfftfreq(pad * len(y), dt), amp


def periodic_spectrum(t: np.ndarray, y: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact Fourier amplitudes of ``y`` sampled at equally spaced ``t`` (n,) s over a whole
    number ``R`` of periods ``period`` (s): no window, no leakage for content periodic over the
    record. Returns the orders ``k / R`` (per period, (n//2 + 1,)) and complex amplitudes
    ``A`` (same rows, then ``y``'s other axes) with ``y(t) = Re Σ A_k exp(i 2π (k/R) t / period)``:
    ``A_0`` the mean, ``|A_k|`` the amplitude of order ``k / R`` (its phase referred to ``t = 0``)."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    n, dt = len(t), float(np.mean(np.diff(t)))
    revs = n * dt / period
    if abs(revs - round(revs)) > 1e-6 * revs or np.abs(np.diff(t) - dt).max() > 1e-9 * dt:
        raise ValueError(f"the record ({n} equally spaced samples, {n * dt:.6g} s) does not cover a whole "
                         f"number of periods of {period:.6g} s")
    k = np.arange(n // 2 + 1)
    phase = np.exp(-2j * np.pi * np.outer(k, t) / (n * dt))
    amp = np.tensordot(phase, y, axes=(1, 0)) * (2.0 / n)
    amp[0] /= 2
    if n % 2 == 0:
        amp[-1] /= 2
    return k / round(revs), amp


def dominant_frequency(t: np.ndarray, y: np.ndarray, fmin: float = 0.0, fmax: float = np.inf) -> float:
    """Frequency (Hz) of the largest spectral peak of ``y`` within ``[fmin, fmax]``."""
    f, a = spectrum(t, y)
    band = (f >= fmin) & (f <= fmax) & (f > 0)
    return float(f[band][np.argmax(a[band])])


def envelope(t: np.ndarray, y: np.ndarray, period: float) -> np.ndarray:
    """Largest ``|y - mean|`` in each whole ``period`` (s) of the record: the amplitude envelope."""
    k = np.floor((t - t[0]) / period).astype(int)
    y = y - np.mean(y)
    return np.array([np.abs(y[k == i]).max() for i in range(k.max())])


def crossing_frequency(t: np.ndarray, y: np.ndarray) -> float:
    """Mean frequency (Hz) from upward crossings of the mean (linear interpolation)."""
    y = y - np.mean(y)
    i = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(1.0 / np.mean(np.diff(tc)))


def hinge_inertia(mass: float, com, inertia) -> np.ndarray:
    """Inertia tensor (3, 3) about the body-frame origin from the one about the centre of mass."""
    c = np.asarray(com, dtype=float)
    return np.asarray(inertia, dtype=float) + mass * (c @ c * np.eye(3) - np.outer(c, c))


def flap_lag_frequencies(mass: float, com, inertia, offset: float, k_flap: float, k_lag: float,
                         omega: float) -> tuple[float, float]:
    """Rotating-frame natural frequencies (per rev) of a rigid blade on coincident flap and lag
    hinges at ``offset`` (m) from the rotation axis, with springs (N m/rad), at ``omega`` (rad/s).

    Blade axes: x along the span, y chordwise, z normal; ``com`` (m) and ``inertia`` (kg m²,
    about the centre of mass) in those axes with the origin at the hinges.
    """
    j = hinge_inertia(mass, com, inertia)
    static = mass * float(np.asarray(com)[0])
    nu_flap2 = (offset * static + j[2, 2] - j[0, 0]) / j[1, 1] + k_flap / (j[1, 1] * omega**2)
    nu_lag2 = offset * static / j[2, 2] + k_lag / (j[2, 2] * omega**2)
    return float(np.sqrt(nu_flap2)), float(np.sqrt(nu_lag2))


def fit_damped_mode(t: np.ndarray, y: np.ndarray, forcing: float, guess: float,
                    harmonics: int = 2) -> tuple[float, float]:
    """Frequency (Hz) and damping ratio of the transient mode in ``y``.

    Model: mean + ``harmonics`` harmonics of the known ``forcing`` frequency (Hz) + one
    exponentially decaying sinusoid; the linear amplitudes are solved by least squares for each
    trial (frequency, decay), which are fitted from ``guess`` (Hz). Separates a free response
    from the periodic forced response even when the record is too short for a spectrum to.
    """
    from scipy.optimize import least_squares

    w0 = 2 * np.pi * forcing
    forced = [np.ones_like(t)] + [f(k * w0 * t) for k in range(1, harmonics + 1) for f in (np.cos, np.sin)]

    def residual(theta):
        w, s = theta
        basis = np.column_stack(forced + [np.exp(-s * t) * np.cos(w * t), np.exp(-s * t) * np.sin(w * t)])
        coef = np.linalg.lstsq(basis, y, rcond=None)[0]
        return basis @ coef - y

    w, s = least_squares(residual, [2 * np.pi * guess, 0.1 * 2 * np.pi * guess]).x
    return float(w / (2 * np.pi)), float(s / np.hypot(w, s))


def azimuth_harmonics(psi: np.ndarray, y: np.ndarray, order: int = 1) -> np.ndarray:
    """Fourier coefficients of ``y`` (n,) sampled uniformly over whole revolutions of the azimuth
    ``psi`` (n,) rad (the end of the last revolution not repeated): ``(a0, a1, b1, ..., a_order,
    b_order)`` with ``y ≈ a0 + Σ a_k cos kψ + b_k sin kψ``."""
    out = [np.mean(y)]
    for k in range(1, order + 1):
        out += [2 * np.mean(y * np.cos(k * psi)), 2 * np.mean(y * np.sin(k * psi))]
    return np.array(out)
