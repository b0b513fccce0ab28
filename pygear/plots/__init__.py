"""Figures drawn from analysis results (Matplotlib on its Agg canvas, without pyplot).

Every plot function returns its :class:`matplotlib.figure.Figure`; the caller saves it
(:func:`pygear.io.save_figure`, at the figure's ``dpi``) or shows it in a notebook.
Titles name the case, the scene and the formulation; every axis carries its units in
brackets; labels that could collide are placed clear of each other
(:mod:`pygear.plots.layout`).
"""
