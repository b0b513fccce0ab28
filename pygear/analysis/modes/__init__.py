"""Natural frequencies and mode shapes: modal analysis and its sensitivities, the
sparse shift-invert solver of large models, the modes of a turning gearbox, Campbell
diagrams and mode tracking across speeds."""
