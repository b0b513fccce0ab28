"""Signals of a run: the channels of a run file, spectra, envelopes and demodulated
resonance analysis on FFTW, peak identification, and computed order tracking."""
