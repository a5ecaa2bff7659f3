/* text_wrap.h: long lines for a terminal: wrapped at word boundaries to its width, whole for a
 * file or a pipe (so grep and scripts see one record a line). Used by `render --explain` and
 * `kernels --check`. */
#ifndef SL_TEXT_WRAP_H
#define SL_TEXT_WRAP_H

#include <stdio.h>

/* The width to wrap at on f: the terminal's (100 when it does not say, at least 60), 0 when f
 * is not a terminal (no wrapping). */
int sl_term_width(FILE *f);

/* text from column col on, wrapped at word boundaries to width (0: not wrapped), later lines
 * indented to indent; a word longer than a line is cut. No newline at the end. */
void sl_put_wrapped(FILE *f, const char *text, int col, int indent, int width);

#endif
