/* SPDX-License-Identifier: MIT */
#include "daemon/out/gpio.h"

#include <dirent.h>
#include <errno.h>
#include <gpiod.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CONSUMER "hdlampd"
#define EVENT_BATCH 16 /* edge events read per read() */

struct hl_gpio {
	struct gpiod_chip *chip;
	char chip_desc[160]; /* "'gpiochip1' [hdlamp]" for messages */
	struct gpiod_line_request *out; /* strobe and ECU-enable, or NULL */
	struct gpiod_line_request *in; /* trigger, or NULL */
	struct gpiod_edge_event_buffer *events;
	int strobe, trigger, ecu_enable; /* offsets, -1 unused */
	unsigned long trigger_seqno; /* line sequence number of the last edge read */
	atomic_int strobe_level;
	_Atomic uint64_t strobe_toggles, strobe_errors;
	_Atomic uint64_t trigger_rising, trigger_falling, trigger_lost;
	_Atomic int64_t trigger_last_ns;
};

/* Appends to msg; a message that does not fit ends in "...". */
static void append(struct hl_gpio_error *err, const char *fmt, ...)
{
	size_t len, size = sizeof(err->msg);
	va_list ap;
	int n;

	len = strlen(err->msg);
	if (len + 1 >= size)
		return;
	va_start(ap, fmt);
	n = vsnprintf(err->msg + len, size - len, fmt, ap);
	va_end(ap);
	if (n >= 0 && (size_t)n >= size - len)
		memcpy(err->msg + size - 4, "...", 4);
}

static int fail(struct hl_gpio_error *err, int code, const char *fmt, ...)
{
	va_list ap;

	if (err) {
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof(err->msg), fmt, ap);
		va_end(ap);
	}
	return code;
}

static int cmp_chip_names(const struct dirent **a, const struct dirent **b)
{
	/* gpiochip2 before gpiochip10 */
	size_t la = strlen((*a)->d_name), lb = strlen((*b)->d_name);

	return la != lb ? (la < lb ? -1 : 1) : strcmp((*a)->d_name, (*b)->d_name);
}

static int is_chip_entry(const struct dirent *d)
{
	return strncmp(d->d_name, "gpiochip", 8) == 0;
}

/* Calls fn for each GPIO chip in /dev with its path and info; stops when fn returns != 0. */
static int each_chip(int (*fn)(const char *path, struct gpiod_chip_info *info, void *ctx),
		     void *ctx)
{
	struct dirent **list;
	int n, r = 0;

	n = scandir("/dev", &list, is_chip_entry, cmp_chip_names);
	if (n < 0)
		return -errno;
	for (int i = 0; i < n; i++) {
		char path[300];
		struct gpiod_chip *c;
		struct gpiod_chip_info *info;

		snprintf(path, sizeof(path), "/dev/%s", list[i]->d_name);
		if (r == 0 && gpiod_is_gpiochip_device(path) && (c = gpiod_chip_open(path))) {
			info = gpiod_chip_get_info(c);
			if (info) {
				r = fn(path, info, ctx);
				gpiod_chip_info_free(info);
			}
			gpiod_chip_close(c);
		}
		free(list[i]);
	}
	free(list);
	return r;
}

struct label_search {
	const char *label;
	char path[300];
};

static int match_label(const char *path, struct gpiod_chip_info *info, void *ctx)
{
	struct label_search *s = ctx;

	if (strcmp(gpiod_chip_info_get_label(info), s->label) != 0)
		return 0;
	snprintf(s->path, sizeof(s->path), "%s", path);
	return 1;
}

struct chip_list {
	struct hl_gpio_error *err;
	int n;
};

static int list_chip(const char *path, struct gpiod_chip_info *info, void *ctx)
{
	struct chip_list *l = ctx;

	append(l->err, "%s%s [%s] (%s, %zu lines)", l->n++ ? ", " : "",
	       gpiod_chip_info_get_name(info), gpiod_chip_info_get_label(info), path,
	       gpiod_chip_info_get_num_lines(info));
	return 0;
}

static int chip_not_found(const char *chip, struct hl_gpio_error *err)
{
	struct chip_list l = { .err = err };

	if (!err)
		return -ENODEV;
	snprintf(err->msg, sizeof(err->msg), "gpio.chip: no GPIO chip '%s'; chips: ", chip);
	each_chip(list_chip, &l);
	if (l.n == 0)
		append(err, "none in /dev (no GPIO driver loaded, or no permission on /dev)");
	return -ENODEV;
}

/* chip: a path (has a '/'), a /dev name or a chip label. */
static int open_chip(const char *chip, struct gpiod_chip **ret, struct hl_gpio_error *err)
{
	struct label_search s = { .label = chip };
	char path[300];
	struct gpiod_chip *c;

	if (strchr(chip, '/')) {
		snprintf(path, sizeof(path), "%s", chip);
	} else {
		snprintf(path, sizeof(path), "/dev/%s", chip);
		if (!gpiod_is_gpiochip_device(path)) {
			if (each_chip(match_label, &s) != 1)
				return chip_not_found(chip, err);
			snprintf(path, sizeof(path), "%s", s.path);
		}
	}
	c = gpiod_chip_open(path);
	if (!c) {
		int e = errno;

		if (e == EACCES || e == EPERM)
			return fail(err, -EACCES,
				    "gpio.chip: '%s' (%s): permission denied (the user needs rw "
				    "access to the chip, e.g. group gpio)",
				    chip, path);
		if (e == ENOENT)
			return chip_not_found(chip, err);
		if (e == ENODEV || e == ENOTTY || e == EINVAL)
			return fail(err, -ENODEV, "gpio.chip: '%s' is not a GPIO chip device",
				    chip);
		return fail(err, -e, "gpio.chip: '%s': %s", chip, strerror(e));
	}
	*ret = c;
	return 0;
}

static bool all_digits(const char *s)
{
	if (!*s)
		return false;
	for (; *s; s++)
		if (*s < '0' || *s > '9')
			return false;
	return true;
}

static void list_lines(struct gpiod_chip *chip, size_t n_lines, struct hl_gpio_error *err)
{
	append(err, " (lines:");
	for (size_t i = 0; i < n_lines; i++) {
		struct gpiod_line_info *li = gpiod_chip_get_line_info(chip, (unsigned)i);
		const char *name = li ? gpiod_line_info_get_name(li) : NULL;

		append(err, "%s %zu \"%s\"", i ? "," : "", i, name ? name : "");
		gpiod_line_info_free(li);
	}
	append(err, ")");
}

/* Resolves a line by name or offset; -1 when spec is empty. */
static int find_line(struct hl_gpio *g, const char *key, const char *spec, int *ret,
		     struct hl_gpio_error *err)
{
	struct gpiod_chip_info *info;
	size_t n_lines;
	long off;

	if (!spec || !*spec) {
		*ret = -1;
		return 0;
	}
	info = gpiod_chip_get_info(g->chip);
	if (!info)
		return fail(err, -errno, "%s: chip %s: %s", key, g->chip_desc, strerror(errno));
	n_lines = gpiod_chip_info_get_num_lines(info);
	gpiod_chip_info_free(info);

	if (all_digits(spec)) {
		off = strlen(spec) > 9 ? -1 : strtol(spec, NULL, 10);
		if (off < 0 || (size_t)off >= n_lines)
			return fail(err, -ENOENT,
				    "%s: chip %s has no line offset %s (%zu lines: 0..%zu)", key,
				    g->chip_desc, spec, n_lines, n_lines ? n_lines - 1 : 0);
		*ret = (int)off;
		return 0;
	}
	off = gpiod_chip_get_line_offset_from_name(g->chip, spec);
	if (off < 0) {
		int e = errno;

		if (e != ENOENT)
			return fail(err, -e, "%s: chip %s: looking up line '%s': %s", key,
				    g->chip_desc, spec, strerror(e));
		if (err) {
			fail(err, 0, "%s: chip %s has no line named '%s'", key, g->chip_desc, spec);
			list_lines(g->chip, n_lines, err);
		}
		return -ENOENT;
	}
	*ret = (int)off;
	return 0;
}

int hl_gpio_edge_parse(const char *s, enum hl_gpio_edge *ret)
{
	if (!s)
		return -EINVAL;
	if (strcmp(s, "rising") == 0)
		*ret = HL_GPIO_EDGE_RISING;
	else if (strcmp(s, "falling") == 0)
		*ret = HL_GPIO_EDGE_FALLING;
	else if (strcmp(s, "both") == 0)
		*ret = HL_GPIO_EDGE_BOTH;
	else
		return -EINVAL;
	return 0;
}

/* A line request; offsets[i] with settings[i]. -errno, err says which lines. */
static int request(struct hl_gpio *g, const unsigned *offsets,
		   struct gpiod_line_settings **settings, size_t n, const char *what,
		   struct gpiod_line_request **ret, struct hl_gpio_error *err)
{
	struct gpiod_request_config *rc;
	struct gpiod_line_config *lc;
	int r = 0;

	rc = gpiod_request_config_new();
	lc = gpiod_line_config_new();
	if (!rc || !lc) {
		r = fail(err, -ENOMEM, "gpio: out of memory");
		goto out;
	}
	gpiod_request_config_set_consumer(rc, CONSUMER);
	for (size_t i = 0; i < n; i++)
		if (gpiod_line_config_add_line_settings(lc, &offsets[i], 1, settings[i]) < 0) {
			r = fail(err, -errno, "gpio: %s: %s", what, strerror(errno));
			goto out;
		}
	*ret = gpiod_chip_request_lines(g->chip, rc, lc);
	if (!*ret) {
		int e = errno;

		if (e == EBUSY)
			r = fail(err, -EBUSY, "%s: chip %s: line busy (held by another consumer)",
				 what, g->chip_desc);
		else
			r = fail(err, -e, "%s: chip %s: requesting the line: %s", what,
				 g->chip_desc, strerror(e));
	}
out:
	gpiod_line_config_free(lc);
	gpiod_request_config_free(rc);
	return r;
}

static struct gpiod_line_settings *settings(enum gpiod_line_direction dir, enum gpiod_line_value v,
					    enum gpiod_line_edge edge)
{
	struct gpiod_line_settings *s = gpiod_line_settings_new();

	if (!s)
		return NULL;
	if (gpiod_line_settings_set_direction(s, dir) < 0 ||
	    (dir == GPIOD_LINE_DIRECTION_OUTPUT &&
	     gpiod_line_settings_set_output_value(s, v) < 0) ||
	    gpiod_line_settings_set_edge_detection(s, edge) < 0 ||
	    gpiod_line_settings_set_event_clock(s, GPIOD_LINE_CLOCK_MONOTONIC) < 0) {
		gpiod_line_settings_free(s);
		return NULL;
	}
	return s;
}

/* The trigger first: if anything fails, ECU-enable has not been driven at all. */
static int request_lines(struct hl_gpio *g, enum hl_gpio_edge edge, struct hl_gpio_error *err)
{
	static const enum gpiod_line_edge kernel_edge[] = {
		[HL_GPIO_EDGE_RISING] = GPIOD_LINE_EDGE_RISING,
		[HL_GPIO_EDGE_FALLING] = GPIOD_LINE_EDGE_FALLING,
		[HL_GPIO_EDGE_BOTH] = GPIOD_LINE_EDGE_BOTH,
	};
	struct gpiod_line_settings *s[2] = { NULL, NULL };
	unsigned offsets[2];
	size_t n = 0;
	int r = 0;

	if (g->trigger >= 0) {
		offsets[0] = (unsigned)g->trigger;
		s[0] = settings(GPIOD_LINE_DIRECTION_INPUT, GPIOD_LINE_VALUE_INACTIVE,
				kernel_edge[edge]);
		g->events = gpiod_edge_event_buffer_new(EVENT_BATCH);
		if (!s[0] || !g->events)
			r = fail(err, -ENOMEM, "gpio: out of memory");
		else
			r = request(g, offsets, s, 1, "gpio.trigger", &g->in, err);
		gpiod_line_settings_free(s[0]);
		s[0] = NULL;
		if (r < 0)
			return r;
	}

	if (g->strobe >= 0) {
		offsets[n] = (unsigned)g->strobe;
		s[n++] = settings(GPIOD_LINE_DIRECTION_OUTPUT, GPIOD_LINE_VALUE_INACTIVE,
				  GPIOD_LINE_EDGE_NONE);
	}
	if (g->ecu_enable >= 0) {
		offsets[n] = (unsigned)g->ecu_enable;
		s[n++] = settings(GPIOD_LINE_DIRECTION_OUTPUT, GPIOD_LINE_VALUE_ACTIVE,
				  GPIOD_LINE_EDGE_NONE);
	}
	for (size_t i = 0; i < n; i++)
		if (!s[i])
			r = fail(err, -ENOMEM, "gpio: out of memory");
	if (r == 0 && n > 0)
		r = request(g, offsets, s, n,
			    g->strobe >= 0 && g->ecu_enable >= 0 ? "gpio.strobe/gpio.ecu_enable" :
			    g->strobe >= 0			 ? "gpio.strobe" :
								   "gpio.ecu_enable",
			    &g->out, err);
	for (size_t i = 0; i < n; i++)
		gpiod_line_settings_free(s[i]);
	return r;
}

static const char *const role_key[3] = { "gpio.strobe", "gpio.trigger", "gpio.ecu_enable" };

int hl_gpio_new(const char *chip, const char *strobe, const char *trigger, const char *trigger_edge,
		const char *ecu_enable, struct hl_gpio **ret, struct hl_gpio_error *err)
{
	enum hl_gpio_edge edge = HL_GPIO_EDGE_RISING;
	struct gpiod_chip_info *info;
	struct hl_gpio *g;
	int off[3], r;

	if (err)
		err->msg[0] = '\0';
	if (!chip || !*chip)
		return fail(err, -EINVAL, "gpio.chip: empty (no GPIO chip configured)");
	if (trigger && *trigger && hl_gpio_edge_parse(trigger_edge, &edge) < 0)
		return fail(err, -EINVAL,
			    "gpio.trigger_edge: '%s' is not one of rising, falling, both",
			    trigger_edge ? trigger_edge : "(null)");
	g = calloc(1, sizeof(*g));
	if (!g)
		return fail(err, -ENOMEM, "gpio: out of memory");
	g->strobe = g->trigger = g->ecu_enable = -1;

	r = open_chip(chip, &g->chip, err);
	if (r < 0)
		goto err_free;
	info = gpiod_chip_get_info(g->chip);
	if (!info) {
		r = fail(err, -errno, "gpio.chip: '%s': %s", chip, strerror(errno));
		goto err_free;
	}
	snprintf(g->chip_desc, sizeof(g->chip_desc), "'%s' [%s]", gpiod_chip_info_get_name(info),
		 gpiod_chip_info_get_label(info));
	gpiod_chip_info_free(info);

	if ((r = find_line(g, role_key[0], strobe, &g->strobe, err)) < 0 ||
	    (r = find_line(g, role_key[1], trigger, &g->trigger, err)) < 0 ||
	    (r = find_line(g, role_key[2], ecu_enable, &g->ecu_enable, err)) < 0)
		goto err_free;
	off[0] = g->strobe, off[1] = g->trigger, off[2] = g->ecu_enable;
	for (int i = 0; i < 3; i++)
		for (int j = i + 1; j < 3; j++)
			if (off[i] >= 0 && off[i] == off[j]) {
				r = fail(err, -EINVAL, "%s and %s: both are line %d of chip %s",
					 role_key[i], role_key[j], off[i], g->chip_desc);
				goto err_free;
			}
	r = request_lines(g, edge, err);
	if (r < 0)
		goto err_free;
	*ret = g;
	return 0;

err_free:
	hl_gpio_free(g);
	return r;
}

void hl_gpio_free(struct hl_gpio *g)
{
	if (!g)
		return;
	/* The ECU must see "disabled" when the daemon goes, whatever the chip does on release. */
	if (g->out && g->ecu_enable >= 0)
		gpiod_line_request_set_value(g->out, (unsigned)g->ecu_enable,
					     GPIOD_LINE_VALUE_INACTIVE);
	if (g->out)
		gpiod_line_request_release(g->out);
	if (g->in)
		gpiod_line_request_release(g->in);
	gpiod_edge_event_buffer_free(g->events);
	if (g->chip)
		gpiod_chip_close(g->chip);
	free(g);
}

int hl_gpio_strobe(struct hl_gpio *g)
{
	int level;

	if (g->strobe < 0)
		return 0;
	level = !atomic_load_explicit(&g->strobe_level, memory_order_relaxed);
	if (gpiod_line_request_set_value(g->out, (unsigned)g->strobe,
					 level ? GPIOD_LINE_VALUE_ACTIVE :
						 GPIOD_LINE_VALUE_INACTIVE) < 0) {
		atomic_fetch_add_explicit(&g->strobe_errors, 1, memory_order_relaxed);
		return -errno;
	}
	atomic_store_explicit(&g->strobe_level, level, memory_order_relaxed);
	atomic_fetch_add_explicit(&g->strobe_toggles, 1, memory_order_relaxed);
	return 0;
}

int hl_gpio_strobe_level(const struct hl_gpio *g)
{
	if (g->strobe < 0)
		return -ENOENT;
	return atomic_load_explicit(&g->strobe_level, memory_order_relaxed);
}

int hl_gpio_trigger_fd(const struct hl_gpio *g)
{
	if (!g->in)
		return -ENOENT;
	return gpiod_line_request_get_fd(g->in);
}

int hl_gpio_read_trigger(struct hl_gpio *g, unsigned *ret_n_edges)
{
	unsigned total = 0;
	int r, n;

	if (!g->in)
		return -ENOENT;
	/* The request's fd blocks on read: only read what poll says is there. */
	while ((r = gpiod_line_request_wait_edge_events(g->in, 0)) > 0) {
		n = gpiod_line_request_read_edge_events(g->in, g->events, EVENT_BATCH);
		if (n < 0)
			return -errno;
		for (int i = 0; i < n; i++) {
			struct gpiod_edge_event *e =
				gpiod_edge_event_buffer_get_event(g->events, i);
			unsigned long seq = gpiod_edge_event_get_line_seqno(e);

			if (g->trigger_seqno && seq > g->trigger_seqno + 1)
				atomic_fetch_add_explicit(&g->trigger_lost,
							  seq - g->trigger_seqno - 1,
							  memory_order_relaxed);
			g->trigger_seqno = seq;
			atomic_fetch_add_explicit(gpiod_edge_event_get_event_type(e) ==
								  GPIOD_EDGE_EVENT_RISING_EDGE ?
							  &g->trigger_rising :
							  &g->trigger_falling,
						  1, memory_order_relaxed);
			atomic_store_explicit(&g->trigger_last_ns,
					      (int64_t)gpiod_edge_event_get_timestamp_ns(e),
					      memory_order_relaxed);
		}
		total += (unsigned)n;
	}
	if (r < 0)
		return -errno;
	*ret_n_edges = total;
	return 0;
}

void hl_gpio_counts(const struct hl_gpio *g, struct hl_gpio_counts *ret)
{
	struct hl_gpio *m = (struct hl_gpio *)g; /* atomic loads of a const object */

	ret->strobe_toggles = atomic_load_explicit(&m->strobe_toggles, memory_order_relaxed);
	ret->strobe_errors = atomic_load_explicit(&m->strobe_errors, memory_order_relaxed);
	ret->trigger_rising = atomic_load_explicit(&m->trigger_rising, memory_order_relaxed);
	ret->trigger_falling = atomic_load_explicit(&m->trigger_falling, memory_order_relaxed);
	ret->trigger_edges = ret->trigger_rising + ret->trigger_falling;
	ret->trigger_lost = atomic_load_explicit(&m->trigger_lost, memory_order_relaxed);
	ret->trigger_last_ns = atomic_load_explicit(&m->trigger_last_ns, memory_order_relaxed);
}
