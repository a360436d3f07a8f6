# The pure-Python benchmark-statistics part of the `ompl` package (PyPI ompl 2.0.1), vendored
# unchanged so tests can load OpenGRASP-rs logs with OMPL's own reader.
