/* A private Xvfb for headless rendering: started on a free display number,
 * waited for until it accepts connections, stopped at the end. */
#include "display.h"
#include "vtk_output.h"

#include "geoscni/error.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

enum {
    FIRST_DISPLAY = 90,    /* display numbers tried: above the usual ones */
    DISPLAY_TRIES = 40,    /* numbers tried before giving up */
    START_ATTEMPTS = 5,    /* servers started before giving up */
    START_WAIT_MS = 10000, /* time a server gets to accept connections */
    POLL_MS = 25
};

static void sleep_ms(long ms)
{
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&t, &t) != 0 && errno == EINTR)
        ;
}

/* Full path of an executable found on PATH, or 0. */
static int find_program(const char *name, char *out, size_t size)
{
    const char *path = getenv("PATH");
    if (!path || !*path)
        path = "/usr/bin:/bin";
    while (*path) {
        size_t length = strcspn(path, ":");
        int n = snprintf(out, size, "%.*s/%s", (int)length, length ? path : ".",
                         name);
        if (n > 0 && (size_t)n < size && access(out, X_OK) == 0)
            return 1;
        path += length + (path[length] == ':');
    }
    return 0;
}

static int display_in_use(int number)
{
    char socket_path[64], lock_path[64];
    snprintf(socket_path, sizeof socket_path, "/tmp/.X11-unix/X%d", number);
    snprintf(lock_path, sizeof lock_path, "/tmp/.X%d-lock", number);
    return access(socket_path, F_OK) == 0 || access(lock_path, F_OK) == 0;
}

static void server_stop(pid_t server)
{
    if (server <= 0)
        return;
    kill(server, SIGTERM);
    for (int waited = 0; waited < START_WAIT_MS; waited += POLL_MS) {
        if (waitpid(server, NULL, WNOHANG) != 0)
            return;
        sleep_ms(POLL_MS);
    }
    kill(server, SIGKILL);
    waitpid(server, NULL, 0);
}

/* The pid the X server that holds :number wrote into its lock file
 * (/tmp/.X<number>-lock, the pid as text), or 0. */
static pid_t display_owner(int number)
{
    char lock_path[64], text[32] = {0};
    snprintf(lock_path, sizeof lock_path, "/tmp/.X%d-lock", number);
    int fd = open(lock_path, O_RDONLY);
    if (fd < 0)
        return 0;
    ssize_t n = read(fd, text, sizeof text - 1);
    close(fd);
    if (n <= 0)
        return 0;
    text[n] = '\0';
    long pid = strtol(text, NULL, 10);
    return pid > 0 ? (pid_t)pid : 0;
}

/* Starts Xvfb on :number; 1 when it accepts connections (DISPLAY set).
 * The display is ours only when its lock file names our server: another
 * post may have started one on the same number a moment before (between
 * display_in_use and here), and rendering on its server would end when
 * that post stops it. */
static int server_start(const char *program, int number, pid_t *server)
{
    char name[32];
    snprintf(name, sizeof name, ":%d", number);
    pid_t child = fork();
    if (child < 0)
        return 0;
    if (child == 0) {
        /* The server goes when post does, even if post is killed. */
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        int null = open("/dev/null", O_RDWR);
        if (null >= 0) {
            dup2(null, STDIN_FILENO);
            dup2(null, STDOUT_FILENO);
            dup2(null, STDERR_FILENO);
        }
        /* -noreset: an X server resets when its last client leaves and
         * refuses connections meanwhile; every render window is a client,
         * so the next one failed now and then ("bad X server connection",
         * a crash in XSync) when the host was busy */
        execl(program, "Xvfb", name, "-screen", "0", "1280x1024x24",
              "-nolisten", "tcp", "-noreset", (char *)NULL);
        _exit(127);
    }
    char socket_path[64];
    snprintf(socket_path, sizeof socket_path, "/tmp/.X11-unix/X%d", number);
    for (int waited = 0; waited < START_WAIT_MS; waited += POLL_MS) {
        if (waitpid(child, NULL, WNOHANG) == child)
            return 0; /* it exited: the number was taken meanwhile */
        pid_t owner = display_owner(number);
        if (owner != 0 && owner != child)
            break; /* another server holds it: ours will give up */
        if (owner == child && access(socket_path, F_OK) == 0) {
            setenv("DISPLAY", name, 1);
            if (gsn_vtk_display_usable()) {
                *server = child;
                return 1;
            }
        }
        sleep_ms(POLL_MS);
    }
    server_stop(child);
    return 0;
}

int gsn_display_open(struct gsn_display *display)
{
    memset(display, 0, sizeof *display);
    display->opened = 1;
    const char *previous = getenv("DISPLAY");
    if (previous && *previous) {
        display->had_previous = 1;
        snprintf(display->previous, sizeof display->previous, "%s", previous);
        if (gsn_vtk_display_usable()) {
            display->available = 1;
            return GSN_OK;
        }
    }
    char program[4096];
    if (!find_program("Xvfb", program, sizeof program)) {
        snprintf(display->reason, sizeof display->reason,
                 "no X display%s and Xvfb is not installed (Debian package "
                 "xvfb)",
                 display->had_previous ? " answers at DISPLAY" : "");
        return GSN_OK;
    }
    int attempts = 0;
    for (int k = 0; k < DISPLAY_TRIES && attempts < START_ATTEMPTS; ++k) {
        int number = FIRST_DISPLAY + k;
        if (display_in_use(number))
            continue;
        ++attempts;
        if (server_start(program, number, &display->server)) {
            display->available = 1;
            return GSN_OK;
        }
    }
    gsn_display_close(display);
    snprintf(display->reason, sizeof display->reason,
             "Xvfb did not start on any of %d free display numbers", attempts);
    return GSN_OK;
}

void gsn_display_close(struct gsn_display *display)
{
    if (!display->opened)
        return;
    server_stop(display->server);
    display->server = 0;
    display->available = 0;
    display->opened = 0;
    if (display->had_previous)
        setenv("DISPLAY", display->previous, 1);
    else
        unsetenv("DISPLAY");
}
