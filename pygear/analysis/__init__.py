"""Analyses: datasets in, datasets out (modes, sensitivities, transients, spectra,
peaks, the accuracy ladder, the constant-speed mesh stiffness).  No figures here."""
