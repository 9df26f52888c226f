"""File formats: parameter sets (`params`), measurement tables (`measurements`), raw test-stand curves (`curves`),
CAN logs and DBC (`can`), units (`units`), atomic writes (`atomic`) and the atomic publication of result folders
with unique work folders (`publish`). Every reader names the file, line or row, column or key of a bad value."""
