/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's GPIO lines (libgpiod v2): a frame strobe output that toggles on every published
 * frame, a capture trigger input with edge detection, and an optional ECU-enable output that is
 * driven active for as long as the object lives (driven inactive and released on free).
 *
 * The chip is a path (/dev/gpiochip0), a device name (gpiochip0, looked up in /dev) or a chip
 * label (e.g. gpio-sim's "hdlamp"). A line is a name as the chip reports it, or a decimal
 * offset when the string is all digits. "" leaves that line unused. Lines are requested with
 * the consumer name "hdlampd"; all are active-high.
 *
 * Thread-safety: hl_gpio_new and hl_gpio_free from one thread (the main thread), with no other
 * call running. hl_gpio_strobe from one thread at a time (the render thread): it neither
 * allocates nor takes a lock, it is one ioctl on the line request. hl_gpio_trigger_fd and
 * hl_gpio_read_trigger from one thread at a time (the event loop). hl_gpio_counts from any
 * thread (the counters are relaxed atomics). The strobe and the trigger are separate line
 * requests, so the render thread and the event loop never share one.
 */
#ifndef HL_DAEMON_OUT_GPIO_H
#define HL_DAEMON_OUT_GPIO_H

#include <stdint.h>

enum hl_gpio_edge {
	HL_GPIO_EDGE_RISING,
	HL_GPIO_EDGE_FALLING,
	HL_GPIO_EDGE_BOTH,
};

struct hl_gpio_counts {
	uint64_t strobe_toggles; /* successful strobe level changes */
	uint64_t strobe_errors; /* hl_gpio_strobe calls whose ioctl failed */
	uint64_t trigger_edges; /* edge events read (rising + falling) */
	uint64_t trigger_rising, trigger_falling;
	uint64_t trigger_lost; /* edges the kernel dropped (gaps in the line's sequence numbers) */
	int64_t trigger_last_ns; /* CLOCK_MONOTONIC time of the last edge read; 0 before one */
};

struct hl_gpio_error {
	char msg[1024]; /* names the chip and the line, and what the system has instead */
};

struct hl_gpio;

/*
 * Opens chip and requests the configured lines: strobe (output, initially inactive),
 * ecu_enable (output, active at once) and trigger (input, edge detection per trigger_edge:
 * "rising", "falling" or "both"). Any line may be "" (unused); NULL is the same as "".
 * Returns 0 and sets *ret, or a negative errno with err->msg set (err may be NULL):
 * -EINVAL bad argument (empty chip, bad edge, the same line twice), -ENODEV no such chip,
 * -ENOENT no such line on the chip, -EACCES no permission on the chip, -EBUSY a line is
 * held by another consumer, -ENOMEM. *ret is untouched on failure.
 */
int hl_gpio_new(const char *chip, const char *strobe, const char *trigger, const char *trigger_edge,
		const char *ecu_enable, struct hl_gpio **ret, struct hl_gpio_error *err);
/* Drives ECU-enable inactive, releases the lines, closes the chip. NULL is a no-op. */
void hl_gpio_free(struct hl_gpio *g);

/* Parses "rising" | "falling" | "both". 0 or -EINVAL. */
int hl_gpio_edge_parse(const char *s, enum hl_gpio_edge *ret);

/*
 * Toggles the strobe line (one published frame = one level change). 0 (also when no strobe
 * line is configured, then nothing is counted) or -errno from the ioctl (counted in
 * strobe_errors; the level is unchanged). Render thread; no allocation, no lock.
 */
int hl_gpio_strobe(struct hl_gpio *g);
/* The strobe's current logical level: 0 or 1; -ENOENT when there is no strobe line. */
int hl_gpio_strobe_level(const struct hl_gpio *g);

/*
 * The trigger's file descriptor, readable (POLLIN) when edge events are pending; owned by g,
 * valid until hl_gpio_free. -ENOENT when there is no trigger line.
 */
int hl_gpio_trigger_fd(const struct hl_gpio *g);
/*
 * Reads every pending edge event without blocking and counts them. *ret_n_edges = the number
 * of edges read by this call (0 if none were pending). 0, -ENOENT (no trigger line) or -errno.
 */
int hl_gpio_read_trigger(struct hl_gpio *g, unsigned *ret_n_edges);

void hl_gpio_counts(const struct hl_gpio *g, struct hl_gpio_counts *ret);

#endif
