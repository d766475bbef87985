#include "batch/child_process.h"

#include "lodforge/error.h"

#include <array>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace lodforge {
namespace {

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

// Appends what the pipe holds now; closes it at its end (the child closed its side).
void drain(int& fd, std::string& into) {
    std::array<char, 65536> buffer{};
    while (fd >= 0) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n > 0) into.append(buffer.data(), static_cast<std::size_t>(n));
        else if (n == 0) close_fd(fd);
        else if (errno == EINTR) continue;
        else if (errno == EAGAIN || errno == EWOULDBLOCK) return;
        else close_fd(fd);
    }
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv) {
    int out[2], err[2];
    if (::pipe2(out, O_CLOEXEC) != 0) throw Error(Error::Kind::io, std::string("cannot create a pipe: ") + std::strerror(errno));
    if (::pipe2(err, O_CLOEXEC) != 0) {
        ::close(out[0]), ::close(out[1]);
        throw Error(Error::Kind::io, std::string("cannot create a pipe: ") + std::strerror(errno));
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    posix_spawn_file_actions_adddup2(&actions, err[1], 2);
    // The batch's own handlers and blocked signals are not the child's: it installs its own.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int rc = ::posix_spawn(&pid_, argv.at(0).c_str(), &actions, &attr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    ::close(out[1]);
    ::close(err[1]);
    if (rc != 0) {
        ::close(out[0]), ::close(err[0]);
        throw_error(Error::Kind::io, argv[0], std::string("cannot start: ") + std::strerror(rc));
    }
    out_fd_ = out[0];
    err_fd_ = err[0];
    ::fcntl(out_fd_, F_SETFL, O_NONBLOCK);
    ::fcntl(err_fd_, F_SETFL, O_NONBLOCK);
}

ChildProcess::~ChildProcess() {
    if (!done_ && pid_ > 0) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, nullptr, 0);
    }
    close_fd(out_fd_);
    close_fd(err_fd_);
}

std::vector<int> ChildProcess::open_fds() const {
    std::vector<int> fds;
    for (int fd : {out_fd_, err_fd_})
        if (fd >= 0) fds.push_back(fd);
    return fds;
}

void ChildProcess::read_available() {
    drain(out_fd_, out_);
    drain(err_fd_, err_);
}

bool ChildProcess::try_reap() {
    if (done_) return true;
    int status = 0;
    pid_t r;
    do r = ::waitpid(pid_, &status, WNOHANG);
    while (r < 0 && errno == EINTR);
    if (r != pid_) return false;
    done_ = true;
    if (WIFEXITED(status)) exit_code_ = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) term_signal_ = WTERMSIG(status);
    // The child is gone: whatever it wrote is in the pipes, whose ends now report EOF.
    for (int fd : {out_fd_, err_fd_})
        if (fd >= 0) ::fcntl(fd, F_SETFL, 0);
    drain(out_fd_, out_);
    drain(err_fd_, err_);
    return true;
}

void ChildProcess::signal(int signal_number) const {
    if (!done_ && pid_ > 0) ::kill(pid_, signal_number);
}

}  // namespace lodforge
