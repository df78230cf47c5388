/* SPDX-License-Identifier: MIT */
/*
 * can/vbus_port and can/vbus_rt: the virtual bus driven in real time by its own thread, with a
 * hook that sends a frame at each of its steps (as the ECU's node does) and ports used from
 * other threads as SocketCAN code uses sockets: every frame arrives once, in order, at the port
 * whose filter takes it; a port sees no frame of its own; the registry finds a bus by name and
 * refuses a second under the same name; a closed port receives nothing more. Run under
 * ThreadSanitizer too (label threads).
 */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "can/vbus.h"
#include "can/vbus_port.h"
#include "can/vbus_rt.h"

#define STEPS 50
#define STEP_NS 1000000 /* 1 ms */
#define SENDS 40

static int64_t mono_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* The hook: a node of its own that sends ID 0x300 with its step number, STEPS times. */
struct stepper {
	struct hl_vbus *bus;
	int node;
	int64_t next;
	int steps;
};

static int64_t step_next(void *ctx)
{
	const struct stepper *s = ctx;

	return s->steps < STEPS ? s->next : INT64_MAX;
}

static int step_run(void *ctx, int64_t t)
{
	struct stepper *s = ctx;
	const uint8_t data[2] = { (uint8_t)s->steps, 0xAA };

	assert_int_equal(hl_vbus_send(s->bus, s->node, t, 0x300, data, 2, false, false), 0);
	s->steps++;
	s->next += STEP_NS;
	return 0;
}

/* Reads frames from a port until n arrived (or 5 s passed). */
static int read_n(struct hl_vbus_port *p, struct hl_vbus_frame *out, int n)
{
	const int64_t until = mono_ns() + 5000000000LL;
	int got = 0;

	while (got < n && mono_ns() < until) {
		struct pollfd pfd = { .fd = hl_vbus_port_fd(p), .events = POLLIN };

		if (hl_vbus_port_read(p, &out[got]) == 1) {
			got++;
			continue;
		}
		poll(&pfd, 1, 100);
	}
	return got;
}

struct sender {
	struct hl_vbus_port *port;
};

static void *send_main(void *arg)
{
	struct sender *s = arg;

	for (int i = 0; i < SENDS; i++) {
		const uint8_t data[1] = { (uint8_t)i };

		assert_int_equal(hl_vbus_port_send(s->port, 0x100, data, 1, false), 0);
		if (i % 8 == 7) {
			struct timespec ts = { 0, 500000 };

			nanosleep(&ts, NULL);
		}
	}
	return NULL;
}

static void vbus_port_in_real_time(void **state)
{
	struct hl_vbus *bus = NULL;
	struct hl_vbus_port *ecu_side = NULL, *all = NULL;
	struct stepper st;
	struct hl_vbus_rt *rt = NULL;
	struct hl_vbus_frame got[STEPS + SENDS];
	const uint32_t only_0x300 = 0x300;
	struct sender snd;
	pthread_t t;
	const struct hl_vbus_rt_hook hook = { step_next, step_run, &st };

	(void)state;
	assert_int_equal(hl_vbus_new(NULL, &bus), 0);
	assert_int_equal(hl_vbus_register("vbus-test", bus), 0);
	assert_int_equal(hl_vbus_register("vbus-test", bus), -EEXIST);
	assert_ptr_equal(hl_vbus_lookup("vbus-test"), bus);
	assert_null(hl_vbus_lookup("vbus-none"));
	assert_int_equal(hl_vbus_port_open(bus, "reader", &only_0x300, 1, &ecu_side), 0);
	assert_int_equal(hl_vbus_port_open(bus, "sender", NULL, 0, &all), 0);
	st = (struct stepper){ .bus = bus, .next = mono_ns() + 5 * STEP_NS };
	st.node = hl_vbus_attach(bus, "stepper", NULL, NULL);
	assert_true(st.node >= 0);
	assert_int_equal(hl_vbus_rt_start(bus, &hook, &rt), 0);
	snd.port = all;
	assert_int_equal(pthread_create(&t, NULL, send_main, &snd), 0);

	/* the reader takes only 0x300: the hook's frames, each once, in its order */
	assert_int_equal(read_n(ecu_side, got, STEPS), STEPS);
	for (int i = 0; i < STEPS; i++) {
		assert_int_equal(got[i].can_id, 0x300);
		assert_int_equal(got[i].data[0], i);
		if (i)
			assert_true(got[i].t_ns > got[i - 1].t_ns);
	}
	/* the sender's port gets the hook's frames, never its own */
	assert_int_equal(read_n(all, got, STEPS), STEPS);
	for (int i = 0; i < STEPS; i++)
		assert_int_equal(got[i].can_id, 0x300);
	pthread_join(t, NULL);
	{
		struct hl_vbus_counts c;
		const int64_t until = mono_ns() + 5000000000LL;

		do { /* the sender's last frames are still on the bus for a moment */
			hl_vbus_counts(bus, &c);
		} while (c.node[1].sent < SENDS && mono_ns() < until);
		assert_int_equal(c.frames, STEPS + SENDS);
	}
	hl_vbus_rt_stop(rt);
	assert_int_equal(hl_vbus_port_read(ecu_side, &got[0]), 0); /* 0x100 was filtered out */
	hl_vbus_port_close(ecu_side);
	hl_vbus_port_close(all);
	hl_vbus_unregister("vbus-test");
	assert_null(hl_vbus_lookup("vbus-test"));
	hl_vbus_free(bus);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(vbus_port_in_real_time),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
