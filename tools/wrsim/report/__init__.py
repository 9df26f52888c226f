"""Reports: bench results (`results`: result.json, waveforms.csv, plots, grids, the index page, atomic publication)
and identification reports (`identification`)."""
