"""Input and output: VTU/PVD frames, ``history.csv`` and ``summary.json`` writers and readers,
off-screen rendering, and the ``fecontact`` command line."""
