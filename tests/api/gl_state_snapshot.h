/* A snapshot of the OpenGL state a plugin may touch, for the "restores every piece of GL state"
 * test of the nephele C API (C99). Table-driven: every entry is one glGet query (plain, indexed
 * or per texture unit); compare two snapshots and the first difference is named. */
#ifndef NEPHELE_TEST_GL_STATE_SNAPSHOT_H
#define NEPHELE_TEST_GL_STATE_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#define GL_STATE_MAX_VALUES 1024

typedef struct gl_state_snapshot {
  size_t count;
  int64_t values[GL_STATE_MAX_VALUES];
  const char* names[GL_STATE_MAX_VALUES]; /* what each value is, for messages */
  int indices[GL_STATE_MAX_VALUES];       /* unit / index of indexed queries, -1 otherwise */
} gl_state_snapshot;

/* Queries everything (the GL context must be current). */
void gl_state_take(gl_state_snapshot* s);
/* 0 if equal; otherwise prints the differences after `what` to stderr and returns their count. */
int gl_state_compare(const gl_state_snapshot* before, const gl_state_snapshot* after, const char* what);

#endif
