/* An X display for VTK's rendering (Debian's VTK renders through GLX only):
 * the one DISPLAY names if it answers, else a private Xvfb started here and
 * stopped by gsn_display_close. */
#ifndef GEOSCNI_POST_DISPLAY_H
#define GEOSCNI_POST_DISPLAY_H

#include <stddef.h>
#include <sys/types.h>

struct gsn_display {
    int opened;         /* open was called: close restores DISPLAY */
    int available;      /* 1 when rendering can go ahead */
    pid_t server;       /* the Xvfb started here, 0 if none */
    int had_previous;   /* DISPLAY was set before */
    char previous[256]; /* its value, restored on close */
    char reason[256];   /* why no display is available */
};

/* Finds or starts a display. No display is not an error: available is 0
 * and reason says why. */
int gsn_display_open(struct gsn_display *display);

/* Stops the Xvfb started by open, if any, and restores DISPLAY. */
void gsn_display_close(struct gsn_display *display);

#endif
