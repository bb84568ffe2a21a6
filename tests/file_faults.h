#pragma once
// Helpers for the tests of how hail treats files that fail: a call that must not hang (a FIFO
// opened for reading blocks until a writer comes), and writes that fail part-way, as on a full
// disk (RLIMIT_FSIZE: a write past the limit fails with EFBIG instead of raising SIGXFSZ).

#include <sys/resource.h>

#include <chrono>
#include <csignal>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>

namespace hail::testing {

/// The message of the E that `call` throws, or "(no exception)" / "(another exception: ...)".
template <class E, class Call>
std::string message_of(Call&& call) {
  try {
    call();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("(another exception: ") + e.what() + ")";
  }
  return "(no exception)";
}

/// What a call that is expected to throw E did, run on its own thread so that a hang is a
/// failed check rather than a test that never ends: the message of the E it threw, "(no
/// exception)", "(another exception: ...)", or nullopt when it had not returned after `limit`
/// (its thread is then left blocked: the test has failed anyway).
template <class E, class Call>
std::optional<std::string> thrown_within(std::chrono::seconds limit, Call call) {
  auto result = std::make_shared<std::promise<std::string>>();
  std::future<std::string> done = result->get_future();
  std::thread([result, call] {
    try {
      call();
      result->set_value("(no exception)");
    } catch (const E& e) {
      result->set_value(e.what());
    } catch (const std::exception& e) {
      result->set_value(std::string("(another exception: ") + e.what() + ")");
    }
  }).detach();
  if (done.wait_for(limit) != std::future_status::ready) return std::nullopt;
  return done.get();
}

/// While alive, files this process writes cannot grow past `bytes`: writes beyond fail
/// (EFBIG), as writes to a full disk do (ENOSPC).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(std::size_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = old_;
    limit.rlim_cur = static_cast<rlim_t>(bytes);
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = SIG_DFL;
};

}  // namespace hail::testing
