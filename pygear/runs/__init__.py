"""Running scenes: the scene runner's outputs, checkpoints, batches, sweeps, the Dask
cluster and progress bars."""
