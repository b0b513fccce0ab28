"""Analyses: datasets in, datasets out.  No figures here.

One subpackage per question, lowest first (a subpackage imports only from those before
it, and from the layers below ``analysis``; ``tests/test_layering.py`` checks it):

- :mod:`~pygear.analysis.contact`: what the teeth give, the mesh stiffness along the
  ideal kinematics (and the loaded tooth contact as it grows);
- :mod:`~pygear.analysis.modes`: natural frequencies and mode shapes, sparse and
  speed-dependent modes, Campbell diagrams, sensitivities;
- :mod:`~pygear.analysis.signals`: spectra, envelopes, DRA, peaks, the channels of a run
  file and computed order tracking;
- :mod:`~pygear.analysis.condition`: the housing sensor's signal, synchronous averages,
  gear condition indicators, the kurtogram;
- :mod:`~pygear.analysis.time`: transient problems, their checks and loads, the accuracy
  ladder;
- :mod:`~pygear.analysis.response`: the periodic steady state across a speed range.
"""
