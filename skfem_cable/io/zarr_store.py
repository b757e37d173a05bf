"""Zarr under the run store: ``atomic_store``, the Zarr store whose every object (chunk
or metadata) is written crash-safely (``atomic.write_atomic``); ``sync``, ``gather`` and
``settled``, which run zarr's coroutines; ``consolidate``, the consolidated metadata of a
group whose arrays are at hand.  zarr is imported on first use.
"""

import asyncio
import dataclasses
import warnings

from ..util.atomic import durable, write_atomic


def sync(coro):
    """Run a zarr coroutine on zarr's event loop (consolidated-metadata warnings off:
    zarr-python reads and writes it; other v3 readers ignore it)."""
    from zarr.core.sync import sync as zarr_sync

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata")
        return zarr_sync(coro)


async def gather(coros):
    """Await all of ``coros`` (none is left running), then raise the first failure."""
    results = await asyncio.gather(*coros, return_exceptions=True)
    for r in results:
        if isinstance(r, BaseException):
            raise r
    return results


async def settled(coros):
    """The results of ``coros``, awaited one after the other (each runs its own reads
    concurrently: all at once would crowd zarr's threads), an ``Exception`` in the place
    of each that failed."""
    results = []
    for coro in coros:
        try:
            results.append(await coro)
        except Exception as err:
            results.append(err)
    return results


async def consolidate(group, arrays):
    """Write the consolidated metadata of ``group`` (an ``AsyncGroup``) from the metadata
    of its ``arrays`` (``{name: AsyncArray}``, all its members): the document
    ``zarr.consolidate_metadata`` writes, without listing the store and reading every
    array's ``zarr.json`` back (a commit of the run store writes it after each append)."""
    from zarr.core.group import ConsolidatedMetadata

    members = ConsolidatedMetadata(metadata={k: a.metadata for k, a in arrays.items()})
    metadata = dataclasses.replace(group.metadata, consolidated_metadata=members)
    await dataclasses.replace(group, metadata=metadata)._save_metadata()


_STORE_CLASS = None


def atomic_store(root, read_only=False):
    """A Zarr store on the folder ``root`` whose writes go through ``write_atomic``
    (zarr is imported on first use)."""
    global _STORE_CLASS
    if _STORE_CLASS is None:
        _STORE_CLASS = _define_store()
    return _STORE_CLASS(root, read_only=read_only)


def _define_store():
    from zarr.storage import LocalStore

    class AtomicStore(LocalStore):
        """``zarr.storage.LocalStore`` writing every object with ``write_atomic`` (its own
        writes are atomic too, but neither durable nor cleaned up after
        ``KeyboardInterrupt``)."""

        def _put(self, key, value, exclusive=False):
            self._check_writable()
            write_atomic(self.root / key, value.as_buffer_like(), exclusive=exclusive)

        async def _write(self, key, value, exclusive=False):
            """``_put`` on a thread when it flushes to the disk (``durable``): the
            ``fsync`` calls of the objects of a commit then overlap; without them a
            write is a copy into the page cache, done on zarr's event loop: handing it
            to a thread cost more than the write (a commit of the 3-element pendulum's
            18 arrays, 52 -> 38 ms of CPU)."""
            if not self._is_open:
                await self._open()
            if durable():
                await asyncio.to_thread(self._put, key, value, exclusive)
            else:
                self._put(key, value, exclusive)

        async def set(self, key, value):
            await self._write(key, value)

        async def set_if_not_exists(self, key, value):
            await self._write(key, value, True)

        def set_sync(self, key, value):
            self._ensure_open_sync()
            self._put(key, value)

    return AtomicStore
