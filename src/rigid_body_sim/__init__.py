# The package's Python side: its messages and services (generated into rigid_body_sim.msg and .srv) and
# rigid_body_sim.testing, the kit for other packages' rostests.
