"""Command line of cnc_motion_sim.sweep (the package in python/ with its `sweep` extra, as in
.venv-full; `make sweep`): `python examples/sweep.py --help`."""
from cnc_motion_sim.sweep import main

if __name__ == "__main__":
    main()
