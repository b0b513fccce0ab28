"""The Fortran kernel: the f2py extension ``_kernel`` and the Python that drives its
time integration (:mod:`.calls`, :mod:`.newmark`, :mod:`.newmark_support`,
:mod:`.newmark_rebase`).  It takes arrays and small settings objects, never a case or an
assembled model: nothing here imports :mod:`pygear.model` or :mod:`pygear.assembly`
(``tests/test_layering.py`` checks it).

This file imports nothing, so that ``pygear.kernel._kernel`` and
``pygear.kernel.calls`` (the foreign-function boundary that assembly uses for the
element matrices) load without the integrator.
"""
