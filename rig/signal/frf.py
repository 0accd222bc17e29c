"""MIMO frequency-response estimation from records: H1, Hv, multiple coherence, conditioning.

Spectral matrices are Welch averages from ``scipy.signal.csd`` (Hann window, 50 % overlap). For
outputs y = H x:
- H1 = (Sxx^-1 Sxy)^T, unbiased by output noise;
- Hv per output: the eigenvector of the smallest eigenvalue of the spectral matrix of [x; y_j], which
  spreads noise over inputs and output (total least squares);
- multiple coherence of output j: the share of its PSD that the inputs explain linearly;
- condition number of H1 per line (large: the inputs are hard to tell apart through the system).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal


@dataclass
class SpectralMatrices:
    """Welch spectral matrices, frequency first: S[f, p, q] = E[conj(P_p) Q_q]."""

    frequency: np.ndarray  # Hz
    sxx: np.ndarray        # (F, n_in, n_in)
    sxy: np.ndarray        # (F, n_in, n_out)
    syy: np.ndarray        # (F, n_out), output auto-spectra

    def __add__(self, other: SpectralMatrices) -> SpectralMatrices:
        return SpectralMatrices(self.frequency, self.sxx + other.sxx, self.sxy + other.sxy, self.syy + other.syy)

    def scaled(self, factor: float) -> SpectralMatrices:
        return SpectralMatrices(self.frequency, self.sxx * factor, self.sxy * factor, self.syy * factor)


@dataclass
class FrfEstimate:
    frequency: np.ndarray   # Hz, (F,)
    h1: np.ndarray          # (F, n_out, n_in)
    hv: np.ndarray          # (F, n_out, n_in)
    coherence: np.ndarray   # (F, n_out), multiple coherence
    condition: np.ndarray   # (F,), condition number of h1


def spectral_matrices(inputs: np.ndarray, outputs: np.ndarray, rate: float, nperseg: int) -> SpectralMatrices:
    """Spectral matrices of inputs (samples x n_in) and outputs (samples x n_out)."""
    kwargs = dict(fs=rate, nperseg=nperseg, axis=0)
    frequency, sxx = signal.csd(inputs[:, :, None], inputs[:, None, :], **kwargs)
    _, sxy = signal.csd(inputs[:, :, None], outputs[:, None, :], **kwargs)
    _, syy = signal.csd(outputs, outputs, **kwargs)
    return SpectralMatrices(frequency, sxx, sxy, syy.real)


def estimate_frf(spectra: SpectralMatrices) -> FrfEstimate:
    """H1, Hv, multiple coherence and condition number from spectral matrices."""
    sxx, sxy, syy = spectra.sxx, spectra.sxy, spectra.syy
    n_in = sxx.shape[1]
    h1 = np.swapaxes(np.linalg.solve(sxx, sxy), 1, 2)  # (F, n_out, n_in)
    explained = np.einsum("foi,fik,fok->fo", h1.conj(), sxx, h1).real
    coherence = np.clip(explained / np.maximum(syy, np.finfo(float).tiny), 0.0, 1.0)
    hv = np.empty_like(h1)
    for j in range(sxy.shape[2]):
        augmented = np.empty((sxx.shape[0], n_in + 1, n_in + 1), complex)
        augmented[:, :n_in, :n_in] = sxx
        augmented[:, :n_in, n_in] = sxy[:, :, j]
        augmented[:, n_in, :n_in] = sxy[:, :, j].conj()
        augmented[:, n_in, n_in] = syy[:, j]
        _, vectors = np.linalg.eigh(augmented)
        smallest = vectors[:, :, 0]  # eigh sorts ascending
        hv[:, j, :] = -smallest[:, :n_in] / smallest[:, n_in:n_in + 1]
    singular = np.linalg.svd(h1, compute_uv=False)
    condition = singular[:, 0] / np.maximum(singular[:, -1], np.finfo(float).tiny)
    return FrfEstimate(spectra.frequency, h1, hv, coherence, condition)
