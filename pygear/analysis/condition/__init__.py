"""Condition monitoring: what the housing sensor records, time-synchronous averages of
shafts and planets, gear condition indicators, spectral kurtosis and the kurtogram."""
