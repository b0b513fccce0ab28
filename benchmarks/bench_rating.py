"""Rating cost: one ISO 6336 rating of the NREL 5 MW gearbox's five meshes (with its four
planet bearings), and a duty cycle of 64 torque bins, each bin a full re-rating.

``python benchmarks/bench_rating.py`` prints the medians of repeats.  The rating is
closed-form, so it should take milliseconds; a duty cycle costs one rating per bin.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import median_seconds  # noqa: E402

from pygear.analysis.rating.gearbox_rating import rate_gearbox  # noqa: E402
from pygear.model.rating import DutyCycle, load_rating  # noqa: E402


def main() -> None:
    case, rating = load_rating("nrel5mw_gearbox")
    single = median_seconds(lambda: rate_gearbox(case, rating), 7, warm_up=True)
    torque = rating.rated_torque * np.linspace(0.05, 1.2, 64)
    hours = np.full(64, rating.service_life_h / 64)
    duty = DutyCycle(tuple(torque), tuple(hours))
    spectrum = median_seconds(lambda: rate_gearbox(case, rating, duty_cycle=duty), 3,
                              warm_up=True)
    print(f"rating, 5 meshes and 4 bearings: {single * 1e3:.1f} ms")
    print(f"duty cycle of 64 bins:           {spectrum * 1e3:.1f} ms "
          f"({spectrum / 64 * 1e3:.2f} ms per bin)")


if __name__ == "__main__":
    main()
