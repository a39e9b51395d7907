/* runstat.c: run a command, then report its wall time, peak memory and status. */
/*
** Usage: lc-runstat cmd [args...]
** After the command ends, prints one line to stderr:
**     runstat wall=<seconds> maxrss_kb=<kilobytes> status=<code>
** and exits with the command's status (128 + signal if it was killed, 127 if
** it could not be started), so it can stand in for the command in a script.
** wait4's ru_maxrss is the child's own peak resident set (Linux counts it in
** kilobytes); the wall clock is CLOCK_MONOTONIC, immune to clock changes.
*/
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>

/* wait4 is BSD, not POSIX: glibc declares it only under _DEFAULT_SOURCE,
** which -D_POSIX_C_SOURCE turns off. Its ABI is stable on every Unix we
** build on, so declare it rather than widen the feature macros. */
pid_t wait4(pid_t pid, int *status, int options, struct rusage *usage);

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: lc-runstat cmd [args...]\n");
        return 2;
    }
    double t0 = now();
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "lc-runstat: cannot fork: %s\n", strerror(errno));
        return 127;
    }
    if (pid == 0) {
        execvp(argv[1], argv + 1);
        fprintf(stderr, "lc-runstat: cannot run '%s': %s\n", argv[1], strerror(errno));
        _exit(127);
    }
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    while (wait4(pid, &status, 0, &ru) < 0) {
        if (errno != EINTR) {
            fprintf(stderr, "lc-runstat: wait4: %s\n", strerror(errno));
            return 127;
        }
    }
    double wall = now() - t0;
    int code = WIFEXITED(status) ? WEXITSTATUS(status)
             : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 127;
    fprintf(stderr, "runstat wall=%.4f maxrss_kb=%ld status=%d\n", wall, ru.ru_maxrss, code);
    return code;
}
