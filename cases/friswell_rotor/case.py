"""Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines* (Cambridge University
Press, 2010), Example 5.9.1: a 1.5 m shaft of 50 mm diameter with two discs, on two
isotropic bearings at its ends.

[Friswell] Example 5.9.1: shaft 1.5 m long, 0.05 m diameter, modelled with six
Timoshenko beam elements; E = 211 GN/m^2, G = 81.2 GN/m^2, rho = 7810 kg/m^3 for
shaft and discs; no internal shaft damping.  Discs keyed at 0.5 m and 1.0 m from one
end: the left 0.07 m thick and 0.28 m in diameter, the right 0.07 m thick and 0.35 m
in diameter.  Bearings at the ends, 1 MN/m in x and y, no stiffness on the rotations,
no damping, no cross-coupling.  The book investigates the machine at 0 and 4000 rev/min
(natural frequencies and whirl; tests/test_rotor.py and docs/rotors.md).
"""

from pygear.model.drivetrain import Drivetrain, Shaft, ShaftBearing, ShaftSection
from pygear.model.rotor import Disc
from pygear.model.rotor_case import RotorCase
from pygear.model.rotor_transient import DiscUnbalance, RotorRun, RotorScene

YOUNG_MODULUS = 211e9  # Pa [Friswell]
SHEAR_MODULUS = 81.2e9  # Pa [Friswell]
DENSITY = 7810.0  # kg/m^3, shaft and discs [Friswell]
SHAFT_DIAMETER = 0.05  # m [Friswell]
BEARING_STIFFNESS = 1e6  # N/m in x and y [Friswell]
# nu = E / (2 G) - 1 = 0.2993; Cowper's solid-circle shear coefficient
# 6 (1 + nu) / (7 + 6 nu), the one ROSS's shaft element takes by default, so that the
# case reproduces ROSS's printout of this example.
POISSON = YOUNG_MODULUS / (2.0 * SHEAR_MODULUS) - 1.0
SHEAR_COEFFICIENT = 6.0 * (1.0 + POISSON) / (7.0 + 6.0 * POISSON)  # ASSUMED (Cowper)

shaft = Shaft(
    name="shaft",
    # three 0.5 m sections, two elements each: the six 0.25 m elements of [Friswell]
    sections=(ShaftSection(0.5, SHAFT_DIAMETER),) * 3,
    young_modulus=YOUNG_MODULUS,
    shear_modulus=SHEAR_MODULUS,
    density=DENSITY,
    elements_per_section=2,
    shear_deformation=True,
    shear_coefficient=SHEAR_COEFFICIENT,
)
# The discs sit on the shaft: their bore is the shaft's diameter [Friswell].
discs = (
    Disc.from_geometry("disc_left", "shaft", 0.5, DENSITY, 0.07, 0.28, SHAFT_DIAMETER),
    Disc.from_geometry("disc_right", "shaft", 1.0, DENSITY, 0.07, 0.35, SHAFT_DIAMETER),
)
bearings = (
    ShaftBearing("bearing_left", "shaft", 0.0, radial=BEARING_STIFFNESS),
    ShaftBearing("bearing_right", "shaft", 1.5, radial=BEARING_STIFFNESS),
)

# An unbalance of 100 g mm on the right disc (51.5 kg): a G 2.5 balance quality at
# 4000 rpm allows e = 6 um, i.e. 310 g mm; the book gives none.
UNBALANCE = 1e-4  # kg m  # ASSUMED (a well-balanced disc, below ISO 1940 G 2.5)
scenes = (
    RotorScene(
        "runup",
        RotorRun(
            duration=3.0,
            # the 2756 rpm critical speed's mode (46 Hz) at 217 steps per period
            time_step=1e-4,
            # 0 to 3500 rpm in 3 s, through the forward critical speeds at 830 and 2756 rpm
            times=(0.0, 3.0),
            speeds_rpm=(0.0, 3500.0),  # ASSUMED (a run-up a machine of this size may take)
            unbalances=(DiscUnbalance("disc_right", UNBALANCE),),
            sample_rate=2000.0,
        ),
        description="run-up from rest to 3500 rpm through two critical speeds",
    ),
    RotorScene(
        "whirl_4000rpm",
        RotorRun(
            duration=0.5,
            time_step=1e-4,
            speeds_rpm=(4000.0,),  # the book's speed of Figure 5.23
            unbalances=(DiscUnbalance("disc_right", UNBALANCE),),
            sample_rate=2000.0,
        ),
        description="4000 rpm from rest: the unbalance response and the free whirl it starts",
    ),
)

case = RotorCase(
    name="friswell_rotor",
    description="Friswell et al. (2010) Example 5.9.1: two discs on a 1.5 m shaft, 1 MN/m bearings",
    drivetrain=Drivetrain(shafts=(shaft,), bearings=bearings, discs=discs),
    scenes=scenes,
)
