"""The commands: the ``placeclust`` CLI and the benchmarks, reports and figures behind it.

Everything here sits above the world, the tasks and the agents, and nothing below imports it.
"""
