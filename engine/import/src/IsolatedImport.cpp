#include "IsolatedImport.h"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>

#include <poll.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "CharacterBlob.h"

// AddressSanitizer and ThreadSanitizer reserve terabytes of address space for their shadow
// memory, so under them any RLIMIT_AS cap stops every parse ("Failed to mmap", "failed to
// allocate"): sanitizer builds parse uncapped.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CC_SHADOW_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define CC_SHADOW_SANITIZER 1
#endif
#endif
#ifndef CC_SHADOW_SANITIZER
#define CC_SHADOW_SANITIZER 0
#endif
#if CC_SHADOW_SANITIZER
#include <sanitizer/common_interface_defs.h>
#endif

namespace cc::detail {
namespace {

#if CC_SHADOW_SANITIZER
// A sanitizer's report in the parse child (assimp reading out of bounds, an allocation past
// max_allocation_size_mb) ends in the death callback that libFuzzer installed for the parent, which
// would save the input as a crash- or oom- finding although the gate contains it. The child dies by
// SIGABRT instead, so the parent reports "the parser crashed" as for any other crash.
void parseChildDied() {
    std::signal(SIGABRT, SIG_DFL);
    std::raise(SIGABRT);
    ::_exit(134);
}
#endif

bool writeAll(int fd, const std::string& data) {
    std::size_t at = 0;
    while (at < data.size()) {
        const ssize_t n = ::write(fd, data.data() + at, data.size() - at);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += std::size_t(n);
    }
    return true;
}

} // namespace

Result<Character> readIsolated(const std::function<Result<Character>()>& read, const std::string& path,
                               double timeoutSeconds, std::size_t memoryBytes) {
    int fds[2];
    if (::pipe(fds) != 0) return read();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return read();
    }
    if (pid == 0) {
        // The child: parse, send the character (or the error) and leave without running any
        // destructor of the parent's state.
        ::close(fds[0]);
        // A crash here is the parser's, contained by this gate: the host's crash handlers (a crash
        // reporter, libFuzzer's artifact writer) must not take it for the host's own.
        for (const int sig : {SIGABRT, SIGBUS, SIGFPE, SIGILL, SIGSEGV}) std::signal(sig, SIG_DFL);
#if CC_SHADOW_SANITIZER
        __sanitizer_set_death_callback(parseChildDied);
#endif
        if (memoryBytes > 0 && !CC_SHADOW_SANITIZER) {
            rlimit limit{};
            limit.rlim_cur = limit.rlim_max = memoryBytes;
            ::setrlimit(RLIMIT_AS, &limit);
        }
        std::string out;
        {
            Result<Character> r = read();
            out = r.isOk() ? "K" + serializeCharacter(r.value()) : "E" + r.status().message();
        }
        ::_exit(writeAll(fds[1], out) ? 0 : 3);
    }
    ::close(fds[1]);
    std::string data;
    bool timedOut = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
    char buffer[1 << 16];
    for (;;) {
        const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
        if (left <= 0.0) {
            timedOut = true;
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int ready = ::poll(&p, 1, int(std::min(left * 1000.0, 1000.0)) + 1);
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) continue;
        const ssize_t n = ::read(fds[0], buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // the child closed its end
        data.append(buffer, std::size_t(n));
    }
    ::close(fds[0]);
    if (timedOut) ::kill(pid, SIGKILL);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (timedOut)
        return Status::invalidArgument(path + ": reading it took longer than " + std::to_string(int(timeoutSeconds)) +
                                       " s (ImportSettings.timeoutSeconds); the parser was stopped");
    if (WIFSIGNALED(status))
        return Status::invalidArgument(path + ": the parser crashed on it (" + std::string(::strsignal(WTERMSIG(status))) +
                                       "): the file is malformed or beyond what assimp 5.2.5 reads");
    if (data.empty() || (WIFEXITED(status) && WEXITSTATUS(status) != 0))
        return Status::invalidArgument(path + ": the parser gave no result (it ran out of memory or stopped early: "
                                              "ImportSettings.maxMemoryBytes)");
    if (data[0] == 'E') return Status::invalidArgument(data.substr(1));
    auto character = deserializeCharacter(data.substr(1));
    if (!character.isOk()) return Status::invalidArgument(path + ": " + character.status().message());
    return character;
}

} // namespace cc::detail
