"""File formats: parameter sets (`params`), measurement tables (`measurements`), raw test-stand curves (`curves`),
CAN logs and DBC (`can`), units (`units`), atomic writes (`atomic`). Every reader names the file, line or row,
column or key of a bad value."""
