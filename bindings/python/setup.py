# SPDX-License-Identifier: GPL-3.0-or-later
"""Only the wheel's tag; everything else is in pyproject.toml.

The package is pure Python over ctypes, so no interpreter or ABI tag applies (py3, none), but the
wheel carries libcagekit and its libraries built for this machine: the platform tag is this one's
(linux_x86_64 here), never `any`, and the wheel is not purelib."""
import sysconfig

from setuptools import Distribution, setup
from wheel.bdist_wheel import bdist_wheel


class BinaryDistribution(Distribution):
    """Carries native libraries: installed to platlib, not purelib."""

    def has_ext_modules(self):
        return True


class PlatformWheel(bdist_wheel):
    def get_tag(self):
        return "py3", "none", sysconfig.get_platform().replace("-", "_").replace(".", "_")


setup(distclass=BinaryDistribution, cmdclass={"bdist_wheel": PlatformWheel})
