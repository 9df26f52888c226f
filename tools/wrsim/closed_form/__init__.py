"""Closed-form reference models the benches check the lowered VHDL-AMS against: the DCPM motor and drive under a
load ramp (`motor`), worm-gear efficiency and ratio (`worm_gear`), the two-mass model (`two_mass`), friction
fits (`friction`)."""
