/* SPDX-License-Identifier: MIT */
/*
 * The capture queue: requests for a capture of the newest published frame (POST /capture,
 * SIGUSR1, the GPIO trigger) and the one thread that writes them (daemon/out/capture.h).
 *
 * A request copies what a capture needs of the newest frame (its header, illuminance, each
 * lamp's distribution and dimming values, its verdict results) into one of `slots` copies made
 * at start, and releases the pool frame at once: no pool frame is held while a capture waits or
 * is written, so the renderer always has its frames. When all slots are taken (captures
 * waiting or being written), a request is refused. The writer thread runs at normal priority
 * and writes one capture at a time, in request order; it logs each result and returns what the
 * capture allocated to the system. Written, failed and refused captures are counted.
 *
 * Thread-safety: submit and counts from any thread, several at once; new, start, stop and free
 * from one thread, stop once no submit runs. The queue holds no lock while it copies or writes.
 */
#ifndef HL_DAEMON_OUT_CAPTURE_QUEUE_H
#define HL_DAEMON_OUT_CAPTURE_QUEUE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "daemon/out/capture.h"
#include "daemon/core/frame_pool.h"

#define HL_CAPTURE_QUEUE_MAX 16 /* capture.queue at most */
#define HL_CAPTURE_FIRST_FRAME_MS 1000 /* a request waits this long for a first frame */
#define HL_CAPTURE_WAIT_MS 20000 /* POST /capture waits this long for its capture's result */

struct hl_capture_queue_config {
	const char *dir; /* capture.dir (copied) */
	int slots; /* captures waiting or being written at once: capture.queue, 1..16 */
	struct hl_frame_pool *pool; /* must outlive the queue */
	struct hl_capture_scene scene; /* copied; what it points to must outlive the queue */
	FILE *log; /* a line per capture ("hdlampd: capture ..."), e.g. stderr; NULL: none */
};

struct hl_capture_queue_counts {
	uint64_t written; /* complete directories */
	uint64_t failed; /* nothing kept: no frame yet, or a file could not be written */
	uint64_t refused; /* every slot taken */
};

struct hl_capture_queue;

/* Allocates the slots' copies of a frame of the pool's shape. 0, -EINVAL, -ENOMEM. */
int hl_capture_queue_new(const struct hl_capture_queue_config *cfg, struct hl_capture_queue **ret);
/* Starts the writer thread; requests queued before are written then. 0 or -errno. */
int hl_capture_queue_start(struct hl_capture_queue *q);
/* Writes what is queued and stops the writer; the counts stay. Later submits: -ESHUTDOWN. */
void hl_capture_queue_stop(struct hl_capture_queue *q);
/* Stops (if running) and frees. NULL is fine. */
void hl_capture_queue_free(struct hl_capture_queue *q);

/*
 * Queues a capture of the newest frame. wait_ms 0: returns 0 once queued (the result is logged
 * and counted); wait_ms > 0: waits that long for it, then 0 with the directory in ret_msg, or
 * -errno with the file and the reason in ret_msg. -EBUSY: every slot is taken (refused); -EAGAIN:
 * no frame was published within HL_CAPTURE_FIRST_FRAME_MS (failed); -ETIMEDOUT: still waiting
 * or being written after wait_ms (its result is logged and counted when it comes);
 * -ESHUTDOWN: the queue is stopping. ret_msg always says what happened. Logged: every
 * capture's result, and with wait_ms 0 a request not taken (the caller does not wait to say it).
 */
int hl_capture_queue_submit(struct hl_capture_queue *q, int wait_ms, char *ret_msg, size_t size);

void hl_capture_queue_counts(struct hl_capture_queue *q, struct hl_capture_queue_counts *ret);

#endif
