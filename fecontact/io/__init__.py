"""Input and output: VTU/PVD frames, ``history.csv`` and ``summary.json`` writers and readers,
run folders and off-screen rendering."""
