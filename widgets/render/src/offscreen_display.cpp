#include "lodforge/render/offscreen_display.h"

#include "lodforge/error.h"

#include <X11/Xlib.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <string>

namespace lodforge::render {

namespace {

bool canOpen(const char* name) {
    Display* display = XOpenDisplay(name);
    if (!display) return false;
    XCloseDisplay(display);
    return true;
}

// The private server, stopped when the process exits normally.
struct PrivateXvfb {
    pid_t pid = -1;
    ~PrivateXvfb() {
        if (pid <= 0) return;
        kill(pid, SIGTERM);
        waitpid(pid, nullptr, 0);
    }
};

PrivateXvfb& privateServer() {
    static PrivateXvfb server;
    return server;
}

// Starts `Xvfb -displayfd`: the server picks a free display number and writes it to the pipe when it
// accepts connections, so there is neither a race for a number nor a sleep.
std::string startXvfb() {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw Error(Error::Kind::io, "cannot start Xvfb: pipe failed");
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw Error(Error::Kind::io, "cannot start Xvfb: fork failed");
    }
    if (pid == 0) {
        // The child: keep only the pipe's write end open across exec; no terminal signals.
        setsid();
        const int out = dup(fds[1]);  // without O_CLOEXEC
        const std::string fd = std::to_string(out);
        const int devnull = open("/dev/null", O_RDWR);
        if (devnull >= 0) {
            dup2(devnull, STDIN_FILENO);
            dup2(devnull, STDOUT_FILENO);
            dup2(devnull, STDERR_FILENO);
        }
        // -noreset: the server would otherwise reset when its last client leaves, and refuse the next
        // connection while it does (the next level of a pack).
        execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
               "-noreset", static_cast<char*>(nullptr));
        _exit(127);
    }
    close(fds[1]);
    privateServer().pid = pid;
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    for (;;) {
        if (poll(&p, 1, 20000) <= 0) break;  // 20 s: a server that has not started by then will not
        char c = 0;
        const ssize_t n = read(fds[0], &c, 1);
        if (n <= 0 || c == '\n') break;
        number += c;
    }
    close(fds[0]);
    if (number.empty()) {
        int status = 0;
        kill(pid, SIGTERM);
        waitpid(pid, &status, 0);
        privateServer().pid = -1;
        const bool missing = WIFEXITED(status) && WEXITSTATUS(status) == 127;
        throw Error(Error::Kind::io, missing ? "rendering needs an X server: DISPLAY is not set and Xvfb is not "
                                              "installed (apt-get install xvfb), or run under xvfb-run"
                                            : "rendering needs an X server: DISPLAY is not set and Xvfb did not "
                                              "start (run under xvfb-run -a)");
    }
    return ":" + number;
}

}  // namespace

void ensureDisplay() {
    static std::mutex mutex;
    const std::lock_guard lock(mutex);
    if (privateServer().pid > 0) return;  // ours, started below, still up (it is stopped at exit only)
    const char* display = std::getenv("DISPLAY");
    if (display && *display) {
        if (canOpen(display)) return;
        throw Error(Error::Kind::io, std::string("rendering needs an X server: cannot open DISPLAY=") + display +
                                         " (unset DISPLAY to let lodforge start a private Xvfb)");
    }
    const std::string name = startXvfb();
    setenv("DISPLAY", name.c_str(), 1);
    if (!canOpen(name.c_str()))
        throw Error(Error::Kind::io, "rendering needs an X server: the private Xvfb on " + name + " refuses connections");
}

}  // namespace lodforge::render
