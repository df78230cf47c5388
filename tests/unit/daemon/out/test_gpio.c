/* SPDX-License-Identifier: MIT */
/*
 * daemon/out/gpio.c against gpio-sim: strobe level changes read back from the simulator, ECU-enable
 * held and released, trigger edges made by pulling the simulated line, and the errors for a
 * missing chip or line.
 *
 * The chip comes from `tests/vm/run --gpio-sim` (HL_GPIO_CHIP, HL_GPIO_SIM; lines hl-strobe,
 * hl-ready, hl-fault, hl-in0..hl-in4 at offsets 0..7). Without it (the host has no GPIO) the
 * cases that need a chip skip, unless HL_GPIO_REQUIRED is set (the vm_gpio ctest sets it):
 * then a missing chip is a failure.
 */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <stdbool.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/out/gpio.h"

#define STROBE 0 /* hl-strobe */
#define READY 1 /* hl-ready */
#define IN0 3 /* hl-in0 */
#define IN1 4 /* hl-in1 */
#define IN2 5 /* hl-in2 */

/* What a failed hl_gpio_new must leave in *ret. */
static int sentinel;
#define SENTINEL ((struct hl_gpio *)&sentinel)

/* Counting allocations on the hot paths (libgpiod's and the render path's included). */
#include "alloc_count.h"

static const char *sim_chip(void)
{
	const char *chip = getenv("HL_GPIO_CHIP");

	if (!chip || !*chip || !getenv("HL_GPIO_SIM")) {
		if (getenv("HL_GPIO_REQUIRED"))
			fail_msg("HL_GPIO_REQUIRED is set but there is no gpio-sim chip "
				 "(HL_GPIO_CHIP, HL_GPIO_SIM unset)");
		skip();
	}
	return chip;
}

static void sim_path(char *buf, size_t size, int offset, const char *attr)
{
	snprintf(buf, size, "%s/sim_gpio%d/%s", getenv("HL_GPIO_SIM"), offset, attr);
}

/* What gpio-sim sees on the line: 0 or 1. */
static int sim_value(int offset)
{
	char path[512], text[16] = "";
	FILE *f;

	sim_path(path, sizeof(path), offset, "value");
	f = fopen(path, "r");
	assert_non_null(f);
	assert_non_null(fgets(text, sizeof(text), f));
	fclose(f);
	assert_true(text[0] == '0' || text[0] == '1');
	return text[0] - '0';
}

static void sim_pull(int offset, const char *pull)
{
	char path[512];
	FILE *f;

	sim_path(path, sizeof(path), offset, "pull");
	f = fopen(path, "w");
	assert_non_null(f);
	assert_true(fputs(pull, f) >= 0);
	assert_int_equal(fclose(f), 0);
}

static void gpio_edge_names_parse(void **state)
{
	enum hl_gpio_edge e = HL_GPIO_EDGE_BOTH;
	(void)state;

	assert_int_equal(hl_gpio_edge_parse("rising", &e), 0);
	assert_int_equal(e, HL_GPIO_EDGE_RISING);
	assert_int_equal(hl_gpio_edge_parse("falling", &e), 0);
	assert_int_equal(e, HL_GPIO_EDGE_FALLING);
	assert_int_equal(hl_gpio_edge_parse("both", &e), 0);
	assert_int_equal(e, HL_GPIO_EDGE_BOTH);
	assert_int_equal(hl_gpio_edge_parse("Rising", &e), -EINVAL);
	assert_int_equal(hl_gpio_edge_parse("", &e), -EINVAL);
	assert_int_equal(hl_gpio_edge_parse(NULL, &e), -EINVAL);
	assert_int_equal(e, HL_GPIO_EDGE_BOTH);
}

static void gpio_empty_chip_and_bad_edge_are_einval(void **state)
{
	struct hl_gpio *g = SENTINEL;
	struct hl_gpio_error err;
	(void)state;

	assert_int_equal(hl_gpio_new("", "hl-strobe", "", "rising", "", &g, &err), -EINVAL);
	assert_non_null(strstr(err.msg, "gpio.chip"));
	assert_int_equal(hl_gpio_new("gpiochip0", "", "hl-in0", "up", "", &g, &err), -EINVAL);
	assert_non_null(strstr(err.msg, "gpio.trigger_edge: 'up'"));
	assert_ptr_equal(g, SENTINEL);
}

static void gpio_missing_chip_is_enodev_naming_it(void **state)
{
	struct hl_gpio *g = SENTINEL;
	struct hl_gpio_error err;
	(void)state;

	assert_int_equal(hl_gpio_new("no-such-chip", "0", "", "rising", "", &g, &err), -ENODEV);
	assert_non_null(strstr(err.msg, "gpio.chip: no GPIO chip 'no-such-chip'; chips: "));
	if (getenv("HL_GPIO_CHIP")) {
		/* The message lists what exists: the simulated chip, its label, path and size. */
		sim_chip();
		assert_non_null(strstr(err.msg, " [hdlamp] ("));
		assert_non_null(strstr(err.msg, getenv("HL_GPIO_CHIP")));
		assert_non_null(strstr(err.msg, ", 8 lines)"));
	} else {
		assert_non_null(strstr(err.msg, "; chips: none in /dev"));
	}
	printf("gpio: %s\n", err.msg);
	assert_int_equal(hl_gpio_new("/dev/gpiochip999", "0", "", "rising", "", &g, &err), -ENODEV);
	assert_non_null(strstr(err.msg, "gpio.chip: no GPIO chip '/dev/gpiochip999'; chips: "));
	assert_int_equal(hl_gpio_new("/dev/null", "0", "", "rising", "", &g, &err), -ENODEV);
	assert_string_equal(err.msg, "gpio.chip: '/dev/null' is not a GPIO chip device");
	assert_ptr_equal(g, SENTINEL);
}

static void gpio_missing_line_is_enoent_naming_it(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio *g = SENTINEL;
	struct hl_gpio_error err;
	(void)state;

	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "hl-nope", "rising", "", &g, &err),
			 -ENOENT);
	assert_non_null(strstr(err.msg, "gpio.trigger: chip '"));
	assert_non_null(strstr(err.msg,
			       "[hdlamp] has no line named 'hl-nope' (lines: 0 \"hl-strobe\", "
			       "1 \"hl-ready\", 2 \"hl-fault\", 3 \"hl-in0\""));
	assert_non_null(strstr(err.msg, "7 \"hl-in4\")"));
	assert_int_equal(hl_gpio_new(chip, "", "", "rising", "8", &g, &err), -ENOENT);
	assert_non_null(strstr(err.msg, "gpio.ecu_enable: chip '"));
	assert_non_null(strstr(err.msg, "has no line offset 8 (8 lines: 0..7)"));
	/* The same line for two jobs. */
	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "", "rising", "0", &g, &err), -EINVAL);
	assert_non_null(strstr(err.msg, "gpio.strobe and gpio.ecu_enable: both are line 0"));
	assert_ptr_equal(g, SENTINEL);
}

static void gpio_chip_by_path_name_or_label(void **state)
{
	const char *chip = sim_chip();
	const char *names[] = { chip, strrchr(chip, '/') + 1, "hdlamp" };
	struct hl_gpio_error err;
	(void)state;

	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
		struct hl_gpio *g = NULL;

		/* Lines by offset this time: 0 is hl-strobe. */
		assert_int_equal(hl_gpio_new(names[i], "0", "", "rising", "", &g, &err), 0);
		assert_int_equal(hl_gpio_strobe_level(g), 0);
		assert_int_equal(hl_gpio_strobe(g), 0);
		assert_int_equal(sim_value(STROBE), 1);
		hl_gpio_free(g);
	}
	hl_gpio_free(NULL);
}

static void gpio_strobe_toggles_equal_sim_changes(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio_counts c;
	struct hl_gpio_error err;
	struct hl_gpio *g;
	int before, now, changes = 0;
	(void)state;

	sim_pull(STROBE, "pull-up"); /* so an undriven line would read 1, not the initial low */
	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "", "rising", "", &g, &err), 0);
	before = sim_value(STROBE);
	assert_int_equal(before, 0); /* requested low */
	for (int i = 0; i < 101; i++) {
		assert_int_equal(hl_gpio_strobe(g), 0);
		now = sim_value(STROBE);
		changes += now != before;
		assert_int_equal(now, hl_gpio_strobe_level(g));
		before = now;
	}
	hl_gpio_counts(g, &c);
	printf("gpio: 101 strobes, %d value changes read back, strobe_toggles %llu, level %d\n",
	       changes, (unsigned long long)c.strobe_toggles, sim_value(STROBE));
	assert_int_equal(changes, 101);
	assert_int_equal(c.strobe_toggles, 101);
	assert_int_equal(c.strobe_errors, 0);
	assert_int_equal(sim_value(STROBE), 1);
	/* No trigger line: the trigger calls say so. */
	assert_int_equal(hl_gpio_trigger_fd(g), -ENOENT);
	unsigned n = 7;
	assert_int_equal(hl_gpio_read_trigger(g, &n), -ENOENT);
	assert_int_equal(n, 7);
	hl_gpio_free(g);
	sim_pull(STROBE, "pull-down");
}

static void gpio_ecu_enable_held_then_released(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio_counts c;
	struct hl_gpio_error err;
	struct hl_gpio *g;
	(void)state;

	sim_pull(READY, "pull-down");
	assert_int_equal(sim_value(READY), 0);
	assert_int_equal(hl_gpio_new(chip, "", "", "rising", "hl-ready", &g, &err), 0);
	assert_int_equal(sim_value(READY), 1);
	/* Nothing else moves it while held: no strobe line, strobe is a counted no-op. */
	assert_int_equal(hl_gpio_strobe(g), 0);
	assert_int_equal(hl_gpio_strobe_level(g), -ENOENT);
	hl_gpio_counts(g, &c);
	assert_int_equal(c.strobe_toggles, 0);
	assert_int_equal(sim_value(READY), 1);
	/* A second user of the line is refused while we hold it. */
	struct hl_gpio *g2 = NULL;
	assert_int_equal(hl_gpio_new(chip, "", "", "rising", "hl-ready", &g2, &err), -EBUSY);
	assert_non_null(strstr(err.msg, "gpio.ecu_enable: chip '"));
	assert_null(g2);
	hl_gpio_free(g);
	assert_int_equal(sim_value(READY), 0);

	/* A start that fails on the trigger leaves ECU-enable alone and released. */
	assert_int_equal(hl_gpio_new(chip, "", "hl-in0", "rising", "", &g, &err), 0);
	assert_int_equal(hl_gpio_new(chip, "", "hl-in0", "rising", "hl-ready", &g2, &err), -EBUSY);
	assert_non_null(strstr(err.msg, "gpio.trigger: chip '"));
	assert_null(g2);
	assert_int_equal(sim_value(READY), 0);
	assert_int_equal(hl_gpio_new(chip, "", "", "rising", "hl-ready", &g2, &err), 0);
	assert_int_equal(sim_value(READY), 1);
	hl_gpio_free(g2);
	hl_gpio_free(g);
	assert_int_equal(sim_value(READY), 0);
}

/* Pulls the trigger line through a sequence and checks what each pull reads. */
static void trigger_sequence(const char *edge, int line, const char *name, int want_rising,
			     int want_falling)
{
	static const char *const pulls[] = { "pull-up", "pull-down", "pull-up", "pull-down" };
	const char *chip = sim_chip();
	struct hl_gpio_counts c;
	struct hl_gpio_error err;
	struct hl_gpio *g;
	unsigned n;
	int fd;

	sim_pull(line, "pull-down");
	assert_int_equal(hl_gpio_new(chip, "", name, edge, "", &g, &err), 0);
	fd = hl_gpio_trigger_fd(g);
	assert_true(fd >= 0);
	assert_int_equal(hl_gpio_read_trigger(g, &n), 0);
	assert_int_equal(n, 0);
	for (size_t i = 0; i < 4; i++) {
		const bool rising = i % 2 == 0;
		const bool want = rising ? want_rising : want_falling;
		struct pollfd p = { .fd = fd, .events = POLLIN };

		sim_pull(line, pulls[i]);
		/* gpio-sim raises the interrupt from a work item: allow for a slow VM. */
		assert_int_equal(poll(&p, 1, want ? 20000 : 500), want ? 1 : 0);
		assert_int_equal(hl_gpio_read_trigger(g, &n), 0);
		assert_int_equal(n, want ? 1 : 0);
		assert_int_equal(hl_gpio_read_trigger(g, &n), 0); /* read once, not twice */
		assert_int_equal(n, 0);
	}
	hl_gpio_counts(g, &c);
	printf("gpio: trigger_edge=%s: %llu rising, %llu falling, %llu lost, last at %lld ns\n",
	       edge, (unsigned long long)c.trigger_rising, (unsigned long long)c.trigger_falling,
	       (unsigned long long)c.trigger_lost, (long long)c.trigger_last_ns);
	assert_int_equal(c.trigger_rising, want_rising ? 2 : 0);
	assert_int_equal(c.trigger_falling, want_falling ? 2 : 0);
	assert_int_equal(c.trigger_edges, c.trigger_rising + c.trigger_falling);
	assert_int_equal(c.trigger_lost, 0);
	assert_true(c.trigger_last_ns > 0);
	hl_gpio_free(g);
	sim_pull(line, "pull-down");
}

static void gpio_trigger_rising_once_per_edge(void **state)
{
	(void)state;
	trigger_sequence("rising", IN0, "hl-in0", 1, 0);
}

static void gpio_trigger_falling_once_per_edge(void **state)
{
	(void)state;
	trigger_sequence("falling", IN1, "hl-in1", 0, 1);
}

static void gpio_trigger_both_once_per_edge(void **state)
{
	(void)state;
	trigger_sequence("both", IN2, "5", 1, 1);
}

/* The render thread's call and the event loop's read allocate nothing. */
static void gpio_strobe_and_trigger_read_do_not_allocate(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio_error err;
	struct hl_gpio *g;
	unsigned n = 0;
	struct hl_gpio *g2 = NULL;
	long counted;
	int r1 = 0, r2;
	(void)state;

	if (!HL_COUNT_ALLOCS)
		skip();
	sim_pull(IN0, "pull-down");
	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "hl-in0", "rising", "", &g, &err), 0);
	sim_pull(IN0, "pull-up");
	struct pollfd p = { .fd = hl_gpio_trigger_fd(g), .events = POLLIN };
	assert_int_equal(poll(&p, 1, 20000), 1);
	allocs = 0;
	for (int i = 0; i < 100 && r1 == 0; i++)
		r1 = hl_gpio_strobe(g);
	r2 = hl_gpio_read_trigger(g, &n);
	counted = allocs;
	allocs = -1;
	assert_int_equal(r1, 0);
	assert_int_equal(r2, 0);
	assert_int_equal(n, 1);
	assert_int_equal(counted, 0);
	/* The counter works: a new object allocates. */
	allocs = 0;
	r1 = hl_gpio_new(chip, "hl-fault", "", "rising", "", &g2, &err);
	counted = allocs;
	allocs = -1;
	assert_int_equal(r1, 0);
	assert_true(counted > 0);
	hl_gpio_free(g2);
	hl_gpio_free(g);
	sim_pull(IN0, "pull-down");
}

#define THREAD_STROBES 2000

static void *render_thread(void *arg)
{
	struct hl_gpio *g = arg;
	long failed = 0;

	for (int i = 0; i < THREAD_STROBES; i++)
		failed += hl_gpio_strobe(g) != 0;
	return (void *)failed;
}

/*
 * As in hdlampd: one thread strobes while another reads trigger edges and a third (here the
 * same) reads the counters. Run under ThreadSanitizer too (docs/daemon.md, GPIO).
 */
static void gpio_strobe_and_trigger_from_two_threads(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio_counts c;
	struct hl_gpio_error err;
	struct hl_gpio *g;
	pthread_t t;
	void *failed;
	unsigned n, edges = 0;
	(void)state;

	sim_pull(IN1, "pull-down");
	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "hl-in1", "both", "", &g, &err), 0);
	assert_int_equal(pthread_create(&t, NULL, render_thread, g), 0);
	for (int i = 0; i < 4; i++) {
		struct pollfd p = { .fd = hl_gpio_trigger_fd(g), .events = POLLIN };

		sim_pull(IN1, i % 2 ? "pull-down" : "pull-up");
		assert_int_equal(poll(&p, 1, 20000), 1);
		assert_int_equal(hl_gpio_read_trigger(g, &n), 0);
		edges += n;
		hl_gpio_counts(g, &c);
		assert_true(c.strobe_toggles <= THREAD_STROBES);
	}
	assert_int_equal(pthread_join(t, &failed), 0);
	assert_null(failed);
	hl_gpio_counts(g, &c);
	assert_int_equal(edges, 4);
	assert_int_equal(c.trigger_rising, 2);
	assert_int_equal(c.trigger_falling, 2);
	assert_int_equal(c.strobe_toggles, THREAD_STROBES);
	assert_int_equal(hl_gpio_strobe_level(g), 0); /* an even number of toggles */
	assert_int_equal(sim_value(STROBE), 0);
	hl_gpio_free(g);
	sim_pull(IN1, "pull-down");
}

/* Strobe, trigger and ECU-enable together, as hdlampd requests them. */
static void gpio_all_three_lines_at_once(void **state)
{
	const char *chip = sim_chip();
	struct hl_gpio_counts c;
	struct hl_gpio_error err;
	struct hl_gpio *g;
	unsigned n;
	(void)state;

	sim_pull(IN0, "pull-down");
	assert_int_equal(hl_gpio_new(chip, "hl-strobe", "hl-in0", "rising", "hl-ready", &g, &err),
			 0);
	assert_int_equal(sim_value(READY), 1);
	assert_int_equal(sim_value(STROBE), 0);
	assert_int_equal(hl_gpio_strobe(g), 0);
	assert_int_equal(sim_value(STROBE), 1);
	assert_int_equal(sim_value(READY), 1); /* the strobe sets its own line only */
	sim_pull(IN0, "pull-up");
	struct pollfd p = { .fd = hl_gpio_trigger_fd(g), .events = POLLIN };
	assert_int_equal(poll(&p, 1, 20000), 1);
	assert_int_equal(hl_gpio_read_trigger(g, &n), 0);
	assert_int_equal(n, 1);
	hl_gpio_counts(g, &c);
	assert_int_equal(c.strobe_toggles, 1);
	assert_int_equal(c.trigger_rising, 1);
	hl_gpio_free(g);
	assert_int_equal(sim_value(READY), 0);
	sim_pull(IN0, "pull-down");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gpio_edge_names_parse),
		cmocka_unit_test(gpio_empty_chip_and_bad_edge_are_einval),
		cmocka_unit_test(gpio_missing_chip_is_enodev_naming_it),
		cmocka_unit_test(gpio_missing_line_is_enoent_naming_it),
		cmocka_unit_test(gpio_chip_by_path_name_or_label),
		cmocka_unit_test(gpio_strobe_toggles_equal_sim_changes),
		cmocka_unit_test(gpio_ecu_enable_held_then_released),
		cmocka_unit_test(gpio_trigger_rising_once_per_edge),
		cmocka_unit_test(gpio_trigger_falling_once_per_edge),
		cmocka_unit_test(gpio_trigger_both_once_per_edge),
		cmocka_unit_test(gpio_strobe_and_trigger_read_do_not_allocate),
		cmocka_unit_test(gpio_strobe_and_trigger_from_two_threads),
		cmocka_unit_test(gpio_all_three_lines_at_once),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
