/* view_test.h — what the viewer's scripted tests share: the display they need (make test
 * runs them under xvfb-run -a) and writing a script or scene file (include
 * <criterion/criterion.h> first). */
#ifndef TEST_VIEW_TEST_H
#define TEST_VIEW_TEST_H

#include <stdio.h>
#include <stdlib.h>

static inline void need_display(void)
{
    if (!getenv("DISPLAY")) cr_skip_test("no DISPLAY: run under xvfb-run -a (make test does)");
}

static inline void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    cr_assert(f, "cannot write %s", path);
    fputs(text, f);
    fclose(f);
}

#endif
