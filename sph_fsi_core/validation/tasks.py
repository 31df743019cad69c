"""Independent runs (validation rungs, sweep points) as tasks: in this process, or on a Dask cluster.

    map_runs(fn, jobs, workers=1, scheduler=None) -> [fn(job) for job in jobs], in order

- workers <= 1 and no scheduler: one after the other, here.
- workers > 1: a dask.distributed LocalCluster of `workers` processes with one task each at a time, each with
  cores / workers Numba threads (more threads than cores makes OpenMP's spinning threads wait on each other and
  runs several times slower). The cluster lives for the call.
- scheduler "tcp://host:8786": an existing cluster, on this machine or others. Start one with
      dask scheduler                                               # prints its address
      NUMBA_NUM_THREADS=<cores per worker> dask worker tcp://host:8786 --nworkers 1 --nthreads 1
  on each machine (the same Python environment and sph_fsi install everywhere; on Slurm, dask-jobqueue's
  SLURMCluster starts the workers as jobs and gives its scheduler's address). Each run writes its files under
  the --out directory as the worker sees it: use a directory every worker shares (NFS, a cluster file system),
  or collect them afterwards; the summaries come back to the caller either way.
A run is the same computation wherever it runs (one run is never split across workers): results equal the
serial ones, to the bit, for the same Numba thread count.
"""
import os

__all__ = ["map_runs"]


def map_runs(fn, jobs, workers=1, scheduler=None):
    jobs = list(jobs)
    if not jobs:
        return []
    if scheduler is None and workers <= 1:
        return [fn(job) for job in jobs]
    from dask.distributed import Client, LocalCluster
    cluster, saved = None, os.environ.get("NUMBA_NUM_THREADS")
    try:
        if scheduler is None:
            threads = max(1, (os.cpu_count() or 1) // workers)
            os.environ["NUMBA_NUM_THREADS"] = str(threads)   # the worker processes inherit it
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=40)
            client = Client(cluster)
        else:
            client = Client(scheduler, timeout="30s")
        try:
            futures = client.map(fn, jobs, pure=False)
            return client.gather(futures)
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()
        if saved is None:
            os.environ.pop("NUMBA_NUM_THREADS", None)
        else:
            os.environ["NUMBA_NUM_THREADS"] = saved
