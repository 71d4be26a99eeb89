"""The run's results: the summary page from its NetCDF outputs (`summary`) and the integrity check of every
output (`verify`)."""
