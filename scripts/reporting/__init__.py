"""The performance report's parts (scripts/report.py, `make report`; scripts/report_multi.py):

    common    paths, errors, running tools, the median
    devices   the devices, the builds of rtl/builds.toml they are measured with, their
              entries in build/report.json and the targets
    flow      synthesis and place and route (Yosys, nextpnr) of a device's build
    timing    timing analysis: nextpnr's critical paths, the SDF's endpoints, the path
              classes over the target period, failing endpoints
    netlist   cells of a synthesised netlist: per module, the iCE40 DSP blocks' stages
              without registers
    simulate  the simulations: the probe (latency, samples per clock, estimator updates)
              and make rtlsim's speed
    markdown  build/report.md: tables and short labels (the method is scripts/README.md's)
"""
