/* Loaded before libgomp into the ngspice processes that run compiled devices (wrsim.backend.ngspice.batch): an
 * OpenMP parallel region runs as a team of one thread, on the calling thread. ngspice 46 opens a parallel region
 * for every load of an OSDI device type, and wrsim's netlists ask for one thread (`set num_threads=1`); libgomp
 * still wakes the region's barrier with a futex system call at its start and at its end, two calls per Newton
 * iteration. A team of one is a valid execution of any parallel region (OpenMP's `if(0)`): worksharing and tasks
 * inside run on this thread, omp_get_num_threads() is 1, the results are the same to the bit
 * (docs/performance.md). The entry point and its arguments are libgomp's (GCC's OpenMP runtime ABI). */
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags);

void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags) {
  (void)num_threads, (void)flags;
  fn(data);
}
