"""Figures drawn from analysis results (Matplotlib, Agg backend)."""
