"""The compiled parts: the ODE model's C core (morphlearn.ode._core), against Debian's libode-dev
0.16 (double precision; optional: without the library the build warns and the other models work,
choosing the ode model then says in one line what to install), and the reduced model's SIMD kernel
(morphlearn.reduced._lanes, plain C, no library; reduced.backend cpu-simd)."""

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
        ),
        Extension(
            "morphlearn.reduced._lanes",
            ["src/morphlearn/reduced/_lanes.c"],
            depends=["src/morphlearn/reduced/_lanes_kernel.h"],
            # the scalar kernel's arithmetic to the last bit: no contraction, no fast-math (the
            # AVX-512 build is chosen at run time inside the file, not by a flag here)
            extra_compile_args=["-O3", "-std=c11", "-ffp-contract=off", "-fno-fast-math", "-Wno-psabi"],
        ),
    ]
)
