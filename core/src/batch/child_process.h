// One child process with its stdout and stderr captured through pipes, for the batch runner: the
// runner polls many of them from one thread (no thread per child), signals them and reaps them.
#pragma once

#include <string>
#include <sys/types.h>
#include <vector>

namespace lodforge {

class ChildProcess {
public:
    // Starts argv[0] (a path) with stdin from /dev/null. Throws Error(io) when it cannot be started.
    explicit ChildProcess(const std::vector<std::string>& argv);
    ~ChildProcess();   // a child still running is killed (SIGKILL) and reaped
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    // The pipe ends still open, for poll(); read_available() drains them without blocking.
    std::vector<int> open_fds() const;
    void read_available();
    // Reaps the child when it has exited (then reads the pipes to their end): true once it is done.
    bool try_reap();
    void signal(int signal_number) const;

    bool done() const { return done_; }
    // After done(): the exit status (0..255), or -1 when a signal ended it (then term_signal()).
    int exit_code() const { return exit_code_; }
    int term_signal() const { return term_signal_; }
    const std::string& out() const { return out_; }
    const std::string& err() const { return err_; }

private:
    pid_t pid_ = -1;
    int out_fd_ = -1, err_fd_ = -1;
    std::string out_, err_;
    bool done_ = false;
    int exit_code_ = -1, term_signal_ = 0;
};

}  // namespace lodforge
