// railvib/signal: spectra of records (FFTW3).
//
// Conventions: one-sided spectra at f_k = k fs / N, k = 0 .. N/2.
//  - amplitudeSpectrum: peak amplitude per line, corrected by the window's
//    coherent gain, so a sine of amplitude A on a line reads A (Hann: within
//    -1.42 dB scalloping between lines; use Window::FlatTop for amplitudes of
//    tones between lines).
//  - powerSpectralDensity: Welch average of windowed segments (50 % overlap),
//    one-sided density in unit^2/Hz normalised by the window power, so its
//    integral over frequency equals the mean square of the record.
// The FFTW planner is serialised internally (plans made with FFTW_ESTIMATE),
// so these functions are safe to call from several threads.
#pragma once

#include <complex>
#include <cstddef>
#include <vector>

namespace railvib::signal {

enum class Window { Rectangular, Hann, FlatTop };

/// Window samples (periodic form for Hann / FlatTop, length n).
std::vector<double> windowSamples(Window window, size_t n);

struct Spectrum {
  std::vector<double> frequency_hz;
  std::vector<double> value;
};

/// Forward real FFT (unnormalised): X_k = sum_n x_n e^{-2 pi i k n / N}, k = 0 .. N/2.
std::vector<std::complex<double>> realFft(const std::vector<double>& x);
/// Inverse of realFft for a record of length n (normalised: irfft(rfft(x)) = x).
std::vector<double> inverseRealFft(const std::vector<std::complex<double>>& spectrum, size_t n);

/// One-sided amplitude spectrum of the whole record (mean not removed).
Spectrum amplitudeSpectrum(const std::vector<double>& x, double fs_hz, Window window = Window::Hann);

/// Welch PSD with segments of `segment_length` samples (clamped to the record), 50 % overlap.
Spectrum powerSpectralDensity(const std::vector<double>& x, double fs_hz, size_t segment_length,
                              Window window = Window::Hann);

}  // namespace railvib::signal
