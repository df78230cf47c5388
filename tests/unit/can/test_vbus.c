/* SPDX-License-Identifier: MIT */
/*
 * can/vbus: arbitration, each node's FIFO, a full queue, run_until / next and FD timing on the
 * bus, with exact times. The wire times come from hl_vbus_wire(), which test_vbus_wire checks
 * against bit strings; here they are added up as the bus schedules frames.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "can/vbus.h"

#define EXT(id) ((id) | HL_DBC_EFF_FLAG)

struct rx_log {
	int n;
	struct hl_vbus_frame f[16];
};

static void on_rx(void *ctx, const struct hl_vbus_frame *f)
{
	struct rx_log *log = ctx;

	assert_true(log->n < 16);
	log->f[log->n++] = *f;
}

static struct hl_vbus *bus_new(void)
{
	struct hl_vbus *b = NULL;

	assert_int_equal(hl_vbus_new(NULL, &b), 0);
	return b;
}

/* The frame's time and, through ret_ifs, with intermission, at 500 kbit/s / 2 Mbit/s. */
static int64_t wire(uint32_t id, const uint8_t *data, uint8_t len, bool fd, bool brs,
		    int64_t *ret_ifs)
{
	return hl_vbus_wire(id, data, len, fd, brs, 500000, 2000000, NULL, NULL, ret_ifs);
}

static void vbus_arbitration_lowest_field_wins(void **state)
{
	struct hl_vbus *b = bus_new();
	struct rx_log log = { 0 };
	struct hl_vbus_counts c;
	int64_t t, ns, ifs;
	int a, x, e, l;

	(void)state;
	a = hl_vbus_attach(b, "a", NULL, NULL);
	x = hl_vbus_attach(b, "x", NULL, NULL);
	e = hl_vbus_attach(b, "e", NULL, NULL);
	l = hl_vbus_attach(b, "listener", on_rx, &log);
	assert_int_equal(l, 3);
	/* All ready at 1000 ns: 0x0FF first; the extended 0x0FF << 18 has the same 11 base bits
	 * but its recessive SRR loses to the standard frame's dominant RTR; it still beats 0x100. */
	assert_int_equal(hl_vbus_send(b, a, 1000, 0x100, NULL, 0, false, false), 0);
	assert_int_equal(hl_vbus_send(b, x, 1000, 0x0ff, NULL, 0, false, false), 0);
	assert_int_equal(hl_vbus_send(b, e, 1000, EXT(0x0ffu << 18), NULL, 0, false, false), 0);
	hl_vbus_run_until(b, 10000000);
	assert_int_equal(log.n, 3);
	assert_int_equal(log.f[0].can_id, 0x0ff);
	assert_int_equal(log.f[1].can_id, EXT(0x0ffu << 18));
	assert_int_equal(log.f[2].can_id, 0x100);
	t = 1000;
	for (int i = 0; i < 3; i++) {
		ns = wire(log.f[i].can_id, NULL, 0, false, false, &ifs);
		assert_int_equal(log.f[i].t_start_ns, t);
		assert_int_equal(log.f[i].t_ns, t + ns);
		t += ifs;
	}
	/* 0x0FF: 47 bits (3 stuff bits), 94 us; the next starts 3 bits of intermission later. */
	assert_int_equal(log.f[0].t_ns, 1000 + 94000);
	assert_int_equal(log.f[1].t_start_ns, 1000 + 100000);
	hl_vbus_counts(b, &c);
	assert_int_equal(c.node[a].arbitration_lost, 2);
	assert_int_equal(c.node[e].arbitration_lost, 1);
	assert_int_equal(c.node[x].arbitration_lost, 0);
	assert_int_equal(c.node[a].max_wait_ns, log.f[2].t_start_ns - 1000);
	assert_int_equal(c.node[l].received, 3);
	assert_int_equal(c.node[a].received, 2);
	assert_int_equal(c.frames, 3);
	assert_int_equal(c.busy_ns, t - 1000);
	assert_string_equal(c.node[l].name, "listener");
	hl_vbus_free(b);
}

static void vbus_fifo_per_node(void **state)
{
	struct hl_vbus *b = bus_new();
	struct rx_log log = { 0 };
	int p, q;

	(void)state;
	p = hl_vbus_attach(b, "p", NULL, NULL);
	q = hl_vbus_attach(b, "q", NULL, NULL);
	hl_vbus_attach(b, "listener", on_rx, &log);
	/* p's 0x100 waits behind p's 0x300, which loses to q's 0x200. */
	hl_vbus_send(b, p, 0, 0x300, NULL, 0, false, false);
	hl_vbus_send(b, p, 0, 0x100, NULL, 0, false, false);
	hl_vbus_send(b, q, 0, 0x200, NULL, 0, false, false);
	hl_vbus_run_until(b, 10000000);
	assert_int_equal(log.n, 3);
	assert_int_equal(log.f[0].can_id, 0x200);
	assert_int_equal(log.f[1].can_id, 0x300);
	assert_int_equal(log.f[2].can_id, 0x100);
	assert_int_equal(log.f[1].node, p);
	hl_vbus_free(b);
}

static void vbus_queue_full(void **state)
{
	struct hl_vbus *b = bus_new();
	struct hl_vbus_counts c;
	int n = hl_vbus_attach(b, "n", NULL, NULL);

	(void)state;
	for (int i = 0; i < HL_VBUS_QUEUE; i++)
		assert_int_equal(hl_vbus_send(b, n, 0, 0x10, NULL, 0, false, false), 0);
	assert_int_equal(hl_vbus_send(b, n, 0, 0x10, NULL, 0, false, false), -ENOBUFS);
	hl_vbus_counts(b, &c);
	assert_int_equal(c.node[n].queue_full, 1);
	/* One frame carried makes room for one. */
	hl_vbus_run_until(b, hl_vbus_next(b));
	assert_int_equal(hl_vbus_send(b, n, 0, 0x10, NULL, 0, false, false), 0);
	assert_int_equal(hl_vbus_send(b, n, 0, 0x10, NULL, 0, false, false), -ENOBUFS);
	hl_vbus_free(b);
}

static void vbus_next_and_run_until(void **state)
{
	static const uint8_t data[] = { 0x11, 0x22, 0x33, 0x44 };
	struct hl_vbus *b = bus_new();
	struct rx_log log = { 0 };
	int64_t end;
	int n;

	(void)state;
	n = hl_vbus_attach(b, "n", NULL, NULL);
	hl_vbus_attach(b, "listener", on_rx, &log);
	assert_true(hl_vbus_next(b) == INT64_MAX);
	/* 0x123 with 11 22 33 44: 77 bits to the end of EOF (test_vbus_wire), 154 us. */
	hl_vbus_send(b, n, 5000, 0x123, data, 4, false, false);
	end = hl_vbus_next(b);
	assert_int_equal(end, 5000 + 154000);
	hl_vbus_run_until(b, end - 1);
	assert_int_equal(log.n, 0);
	assert_int_equal(hl_vbus_now(b), end - 1);
	hl_vbus_run_until(b, end);
	assert_int_equal(log.n, 1);
	assert_int_equal(log.f[0].t_ns, end);
	assert_memory_equal(log.f[0].data, data, 4);
	assert_true(hl_vbus_next(b) == INT64_MAX);
	/* Ready in the past means now; the bus is free again 3 bits after EOF. */
	hl_vbus_send(b, n, 0, 0x123, data, 4, false, false);
	assert_int_equal(hl_vbus_next(b), end + 6000 + 154000);
	/* A frame ready while the bus is busy starts when it is free. */
	hl_vbus_send(b, n, end + 10000, 0x124, NULL, 0, false, false);
	hl_vbus_run_until(b, INT64_MAX - 1);
	assert_int_equal(log.n, 3);
	assert_int_equal(log.f[2].t_start_ns, end + 6000 + 160000);
	hl_vbus_free(b);
}

static void vbus_fd_timing(void **state)
{
	static const uint8_t data[12] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11 };
	struct hl_vbus *b = bus_new();
	struct rx_log log = { 0 };
	int n;

	(void)state;
	n = hl_vbus_attach(b, "n", NULL, NULL);
	hl_vbus_attach(b, "listener", on_rx, &log);
	hl_vbus_send(b, n, 0, 0x123, data, 12, true, true);
	hl_vbus_send(b, n, 0, 0x123, data, 12, true, false);
	hl_vbus_run_until(b, 1000000);
	assert_int_equal(log.n, 2);
	/* test_vbus_wire's frames: 123500 ns with BRS (129500 with intermission), 332000 without */
	assert_int_equal(log.f[0].t_ns, 123500);
	assert_true(log.f[0].fd && log.f[0].brs);
	assert_int_equal(log.f[1].t_start_ns, 129500);
	assert_int_equal(log.f[1].t_ns, 129500 + 332000);
	hl_vbus_free(b);
}

static void vbus_errors(void **state)
{
	const struct hl_vbus_config fast = { .bitrate = 16000001 };
	const struct hl_vbus_config long_name = { .name = "a-name-longer-than-ifnamsiz" };
	struct hl_vbus *b = NULL;
	uint8_t data[64] = { 0 };
	char name[8];

	(void)state;
	assert_int_equal(hl_vbus_new(&fast, &b), -EINVAL);
	assert_int_equal(hl_vbus_new(&long_name, &b), -EINVAL);
	b = bus_new();
	assert_int_equal(hl_vbus_send(b, 0, 0, 0x1, NULL, 0, false, false), -EINVAL);
	for (int i = 0; i < HL_VBUS_MAX_NODES; i++) {
		snprintf(name, sizeof(name), "n%d", i);
		assert_int_equal(hl_vbus_attach(b, name, NULL, NULL), i);
	}
	assert_int_equal(hl_vbus_attach(b, "one-too-many", NULL, NULL), -ENOSPC);
	assert_int_equal(hl_vbus_send(b, 8, 0, 0x1, NULL, 0, false, false), -EINVAL);
	assert_int_equal(hl_vbus_send(b, 0, 0, 0x1, data, 9, false, false), -EINVAL);
	assert_int_equal(hl_vbus_send(b, 0, 0, 0x1, data, 13, true, false), -EINVAL);
	assert_int_equal(hl_vbus_send(b, 0, 0, 0x800, data, 1, false, false), -EINVAL);
	assert_int_equal(hl_vbus_send(b, 0, 0, EXT(0x20000000u), data, 1, false, false), -EINVAL);
	assert_int_equal(hl_vbus_trace(b, "/tmp/x.txt", 0), -EINVAL);
	hl_vbus_free(b);
	hl_vbus_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(vbus_arbitration_lowest_field_wins),
		cmocka_unit_test(vbus_fifo_per_node),
		cmocka_unit_test(vbus_queue_full),
		cmocka_unit_test(vbus_next_and_run_until),
		cmocka_unit_test(vbus_fd_timing),
		cmocka_unit_test(vbus_errors),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
