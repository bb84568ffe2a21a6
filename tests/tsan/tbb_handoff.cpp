// Self-check of the ThreadSanitizer set-up (scripts/sanitizers.sh tsan), run before the tests:
//   tbb_handoff          elements written by parallel_for's tasks and read after it returns:
//                        must give no report. TSan sees TBB's hand-offs only when libtbb is
//                        built with -fsanitize=thread; with Debian's libtbb this reports a race.
//   tbb_handoff racy     the same, then two tasks that meet (so that they surely run on two
//                        threads) and both add to one int unsynchronised: must be reported, and
//                        halt_on_error must make the report fail the run.

#include <atomic>
#include <cstdio>
#include <cstring>
#include <vector>

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

int main(int argc, char** argv) {
  const bool racy = argc > 1 && std::strcmp(argv[1], "racy") == 0;
  tbb::global_control two_threads(tbb::global_control::max_allowed_parallelism, 2);  // even on 1 core
  tbb::task_arena arena(2);
  std::vector<int> out(1000, 0);
  for (int rep = 0; rep < 20; ++rep) arena.execute([&] { tbb::parallel_for(0, 1000, [&](int i) { out[i] += i; }); });
  long sum = 0;
  for (int v : out) sum += v;

  int shared = 0;
  if (racy) {
    std::atomic<int> started{0};
    auto task = [&] {
      started.fetch_add(1);
      while (started.load() < 2) {
      }             // both tasks are running, so on two threads
      shared += 1;  // the planted race
    };
    arena.execute([&] {
      tbb::task_group g;
      g.run(task);
      g.run(task);
      g.wait();
    });
  }
  std::printf("sum %ld, shared %d\n", sum, shared);
  return 0;
}
