"""Command line of cnc_motion_sim.cosim (the package in python/, installed in .venv by `make venv`):
`python examples/cosim.py --help`."""
from cnc_motion_sim.cosim import main

if __name__ == "__main__":
    main()
