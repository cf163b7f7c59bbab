"""Command line of cnc_motion_sim.ssp (the package in python/; `make ssp` writes examples/cosim.ssp):
`python examples/make_ssp.py --help`."""
from cnc_motion_sim.ssp import main

if __name__ == "__main__":
    main()
