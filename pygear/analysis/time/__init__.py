"""Time integration: transient problems from scenes, their checks before a run, the
drive and load laws, the layout of a run's channels, and the accuracy ladder."""
