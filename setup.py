"""The one compiled part: the ODE model's C core (morphlearn.ode._core), against Debian's
libode-dev 0.16 (double precision). Optional: without the library the build warns and the other
models work; choosing the ode model then says in one line what to install."""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "morphlearn.ode._core",
            ["src/morphlearn/ode/_core.c"],
            libraries=["ode"],
            # portable results: no fast-math, no FMA contraction (the x86-64 baseline has no FMA)
            extra_compile_args=["-O2", "-std=c11", "-ffp-contract=off", "-fno-fast-math"],
            optional=True,
        )
    ]
)
