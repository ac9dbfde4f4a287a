#pragma once
/// Test support: child processes (spawned, output to a file, killed on destruction), a RouDi
/// for the duration of a test, temporary folders, and unique topic namespaces.
#include <sys/types.h>

#include <string>
#include <vector>

#include "dds/participant.hpp"

namespace df::test {

class ChildProcess {
  public:
    /// Starts argv[0] (a path) with argv; stdout+stderr go to log_path.
    ChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
                 const std::vector<std::string>& extra_env = {});
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    pid_t pid() const { return pid_; }
    /// Waits up to timeout_s for exit; returns the exit status, 128+signal, or -1 on timeout.
    int wait(double timeout_s);
    void kill(int signal);
    bool running();
    std::string output() const;

  private:
    pid_t pid_ = -1;
    int status_ = -1;
    bool exited_ = false;
    std::string log_path_;
};

/// True when a RouDi runs (the CTest fixture "roudi" starts one; a test process cannot own
/// it, because RouDi sends SIGTERM to every registered process when it stops).
bool roudi_available();

/// A participant on shared memory (domain 0); fails the calling test if it cannot be made.
dds::Participant shm_participant();

/// A fresh folder under $TMPDIR, removed at destruction.
class TempDir {
  public:
    TempDir();
    ~TempDir();
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

/// A topic namespace unique to this process and call (shared memory leaks across domains).
std::string unique_ns(const std::string& stem);

/// Directory of the built binaries and of the source tree (compile definitions).
std::string bin_dir();
std::string source_dir();

}  // namespace df::test
