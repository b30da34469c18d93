"""The explorer's kernel manager: Jupyter Server's, with a cap on the kernels alive at once.

Voila starts a kernel (about 320 MB) for every page request; six bare GETs made six kernels and
2 GB until the culler ended them (``morphlearn explore``'s ``VOILA_CULL``: about 75 s). Past
:attr:`CappedKernelManager.max_kernels` a request is answered 503 with the reason, and no kernel is
started. Imported by Voila only (``--VoilaConfiguration.multi_kernel_manager_class``).
"""

from __future__ import annotations

from typing import Any

from jupyter_server.services.kernels.kernelmanager import AsyncMappingKernelManager
from tornado.web import HTTPError
from traitlets import Integer

#: Kernels alive at once by default: a few tabs of one reviewer, about 1.3 GB.
MAX_KERNELS = 4


class CappedKernelManager(AsyncMappingKernelManager):
    """At most ``max_kernels`` kernels alive; a new one past that is refused (HTTP 503)."""

    max_kernels = Integer(MAX_KERNELS, config=True, help="kernels alive at once at most")

    async def start_kernel(self, *args: Any, **kwargs: Any) -> str:
        if kwargs.get("kernel_id") is None and len(self.list_kernel_ids()) >= self.max_kernels:
            raise HTTPError(
                503,
                reason=f"the explorer runs at most {self.max_kernels} pages at once (about 320 MB each); "
                "close a tab, or wait a minute: an idle page's kernel ends after 60 s",
            )
        return await super().start_kernel(*args, **kwargs)
