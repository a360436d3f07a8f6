# As ompl/tools.py of PyPI ompl 2.0.1, without the compiled bindings.
from ._benchmark_statistics import (  # noqa: F401
    readBenchmarkLog,
    saveAsMysql,
    computeViews,
)
