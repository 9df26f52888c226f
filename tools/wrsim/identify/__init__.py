"""Parameter identification (thesis 4.1.1.3-4.1.1.4, 4.1.3, 4.1.4.2, Appendix B): the thesis's parameter
calculator and default set (`calculator`), group identification from raw test-stand files (`fit`), parameter
sets and temperature sets from identifications (`paramset`), synthetic test-stand data (`synthetic`), the
validation report (`report`), and the command that runs one identification from files (`command`)."""

from __future__ import annotations

from wrsim.identify.calculator import (
    gear_efficiency_from_slopes,
    housing_friction_from_gap,
    identify_default_set,
    least_squares_motor,
    line_fit,
    motor_from_line,
    parameter_calculator,
    write_default_set,
)
from wrsim.identify.fit import (
    CurveFit,
    DamperIdentification,
    DriveIdentification,
    GroupLines,
    MotorIdentification,
    Validation,
    fit_curve,
    group_lines,
    identify_damper,
    identify_drive,
    identify_motor,
    validate,
)
from wrsim.identify.paramset import temperature_set, write_identified_set

__all__ = [
    "gear_efficiency_from_slopes",
    "housing_friction_from_gap",
    "identify_default_set",
    "least_squares_motor",
    "line_fit",
    "motor_from_line",
    "parameter_calculator",
    "write_default_set",
    "CurveFit",
    "DamperIdentification",
    "DriveIdentification",
    "GroupLines",
    "MotorIdentification",
    "Validation",
    "fit_curve",
    "group_lines",
    "identify_damper",
    "identify_drive",
    "identify_motor",
    "validate",
    "temperature_set",
    "write_identified_set",
]
