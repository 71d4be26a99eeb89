"""Figure functions: take datasets, return matplotlib Figures (Agg backend, no file I/O)."""
