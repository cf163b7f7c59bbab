"""Command line of cnc_motion_sim.cosim (the package in python/; the own master runs in `make demo`'s
.venv, libcosim and Ecos need the `cosim` extra, as in .venv-full): `python examples/cosim.py --help`."""
from cnc_motion_sim.cosim import main

if __name__ == "__main__":
    main()
