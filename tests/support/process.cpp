#include "process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "dds/participant.hpp"

extern char** environ;

namespace df::test {

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
                           const std::vector<std::string>& extra_env)
    : log_path_(log_path) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<std::string> env_store;
    for (char** e = environ; *e != nullptr; ++e) env_store.emplace_back(*e);
    for (const auto& e : extra_env) env_store.push_back(e);
    std::vector<char*> env;
    for (auto& e : env_store) env.push_back(e.data());
    env.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    if (posix_spawn(&pid_, args[0], &fa, nullptr, args.data(), env.data()) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0 && !exited_) {
        ::kill(pid_, SIGKILL);
        wait(5);
    }
}

int ChildProcess::wait(double timeout_s) {
    if (pid_ <= 0) return -1;
    if (exited_) return status_;
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (true) {
        int st = 0;
        const pid_t r = ::waitpid(pid_, &st, WNOHANG);
        if (r == pid_) {
            exited_ = true;
            status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            return status_;
        }
        if (std::chrono::steady_clock::now() >= deadline) return -1;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

void ChildProcess::kill(int signal) {
    if (pid_ > 0 && !exited_) ::kill(pid_, signal);
}

bool ChildProcess::running() { return pid_ > 0 && wait(0) == -1; }

std::string ChildProcess::output() const {
    std::ifstream in(log_path_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

bool roudi_available() {
    for (int i = 0; i < 100; ++i) {
        if (dds::roudi_running()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
}

dds::Participant shm_participant() {
    dds::ParticipantConfig pc;
    pc.transport = dds::Transport::kSharedMemory;
    auto p = dds::Participant::create(pc);
    EXPECT_TRUE(p.is_ok()) << p.status().to_string();
    return std::move(*p);
}

TempDir::TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string tmpl = std::string(base != nullptr ? base : "/tmp") + "/dftest-XXXXXX";
    char* p = mkdtemp(tmpl.data());
    path_ = p != nullptr ? p : "";
}

TempDir::~TempDir() {
    if (!path_.empty() && std::getenv("DF_KEEP_TEST_FILES") == nullptr) {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
}

std::string unique_ns(const std::string& stem) {
    static int counter = 0;
    return "t" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + stem;
}

std::string bin_dir() { return DF_TEST_BIN_DIR; }
std::string source_dir() { return DF_TEST_SOURCE_DIR; }

}  // namespace df::test
