/* SPDX-License-Identifier: MIT */
/*
 * A CAN database read from a .dbc file (docs/dbc.md): messages, signals, multiplexing,
 * attributes, value tables and comments, plus the codec that turns frames into physical values.
 *
 * The database object is opaque; the message and signal descriptions it hands out are public,
 * read-only structs owned by the database and valid until hl_dbc_free(). Their fields marked
 * "codec" are precomputed by the parser for the decoder and are not meant for callers.
 *
 * Thread-safety: a database is built by one thread; once built it is read-only and may be used
 * (looked up, decoded with) from any number of threads at once. Decoding allocates nothing;
 * per-frame events are counted in a caller-owned struct hl_dbc_counters.
 */
#ifndef HL_DBC_DATABASE_H
#define HL_DBC_DATABASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define HL_DBC_MAX_PAYLOAD 64 /* bytes, CAN FD */
#define HL_DBC_MAX_SIGNALS 4096 /* per message */
#define HL_DBC_EFF_FLAG 0x80000000u /* extended ID, as CAN_EFF_FLAG in <linux/can.h> */

/* Where a file broke and what was expected there. line and column are 1-based; 0 when the
 * fault has no place (file missing, out of memory). */
struct hl_dbc_error {
	int line, column;
	char msg[256];
};

enum hl_dbc_byte_order {
	HL_DBC_MOTOROLA = 0, /* @0: big endian, start bit is the MSB (sawtooth numbering) */
	HL_DBC_INTEL = 1, /* @1: little endian, start bit is the LSB */
};

enum hl_dbc_value_type {
	HL_DBC_INTEGER, /* SIG_VALTYPE_ 0 (or none) */
	HL_DBC_FLOAT, /* SIG_VALTYPE_ 1: IEEE 754 single, 32 bits */
	HL_DBC_DOUBLE, /* SIG_VALTYPE_ 2: IEEE 754 double, 64 bits */
};

enum hl_dbc_object {
	HL_DBC_NETWORK,
	HL_DBC_NODE, /* BU_ */
	HL_DBC_MESSAGE, /* BO_ */
	HL_DBC_SIGNAL, /* SG_ */
	HL_DBC_ENVVAR, /* EV_ (definitions kept, values ignored) */
};

enum hl_dbc_attr_type {
	HL_DBC_ATTR_INT,
	HL_DBC_ATTR_HEX,
	HL_DBC_ATTR_FLOAT,
	HL_DBC_ATTR_STRING,
	HL_DBC_ATTR_ENUM,
};

/* An attribute value: i for INT, HEX and ENUM (the index), f for FLOAT (and i as double for
 * the integer types), s for STRING and ENUM (the label). s is owned by the database. */
struct hl_dbc_attr_value {
	enum hl_dbc_attr_type type;
	int64_t i;
	double f;
	const char *s;
};

/* BA_DEF_ (+ BA_DEF_DEF_). */
struct hl_dbc_attr_def {
	const char *name;
	enum hl_dbc_object object;
	enum hl_dbc_attr_type type;
	double min, max; /* INT, HEX, FLOAT; no range check when min == max */
	int n_labels; /* ENUM */
	const char *const *labels;
	bool has_default;
	struct hl_dbc_attr_value def;
};

/* One entry of a VAL_ or VAL_TABLE_ description. */
struct hl_dbc_value_desc {
	int64_t value;
	const char *desc;
};

/* A multiplexor value range [lo, hi] (SG_MUL_VAL_; mN is [N, N]). */
struct hl_dbc_mux_range {
	uint64_t lo, hi;
};

/* codec: how to pull the signal out of a frame padded by 8 zero bytes. */
struct hl_dbc_extract {
	uint16_t byte; /* first byte read */
	uint8_t shift; /* Intel: right shift of the LE word; Motorola: left shift of the BE word */
	uint8_t len; /* bits */
	uint64_t mask; /* low len bits */
	uint64_t sign; /* the sign bit for signed integers, else 0 */
};

struct hl_dbc_signal {
	const char *name;
	int index; /* in its message */
	int start_bit; /* as in the file: LSB (Intel) or MSB in sawtooth numbering (Motorola) */
	int length; /* bits, 1..64 */
	enum hl_dbc_byte_order order;
	bool is_signed;
	enum hl_dbc_value_type type;
	double factor, offset, min, max;
	const char *unit;
	const char *comment; /* CM_ SG_, or NULL */
	int n_receivers;
	const char *const *receivers;
	int n_values; /* VAL_ */
	const struct hl_dbc_value_desc *values;
	/* Multiplexing: a multiplexor (M or mNM) selects which of its dependents are present. A
	 * dependent names its multiplexor (mux_parent, an index in the message, -1 when always
	 * present) and the multiplexor values for which it is present. */
	bool is_multiplexor;
	int mux_parent;
	int n_mux_ranges;
	const struct hl_dbc_mux_range *mux_ranges;
	int line; /* of its SG_ */
	/* It extends past its message (a lenient load warned): never decoded, never present. */
	bool unusable;
	struct hl_dbc_extract x; /* codec */
	int mux_table; /* codec: index of its dependents table, -1 */
};

struct hl_dbc_message {
	const char *name;
	uint32_t id; /* 11 or 29 bits */
	bool extended;
	bool independent; /* VECTOR__INDEPENDENT_SIG_MSG: holds unused signals, never on the bus */
	uint32_t can_id; /* id | HL_DBC_EFF_FLAG when extended: the key of hl_dbc_find_id() */
	int size; /* bytes, 0..64; a frame must have at least this many */
	const char *transmitter; /* NULL for Vector__XXX */
	int n_tx_nodes; /* BO_TX_BU_ */
	const char *const *tx_nodes;
	const char *comment; /* CM_ BO_, or NULL */
	int n_signals;
	const struct hl_dbc_signal *signals;
	int line; /* of its BO_ */
	const struct hl_dbc_plan *plan; /* codec */
};

/* One decoded signal: its index in the message, the raw bits (sign-extended for signed
 * integers, the IEEE bit pattern for float and double) and the physical value. */
struct hl_dbc_value {
	uint32_t signal;
	uint64_t raw;
	double phys;
};

/* Per-frame events, owned and summed by the caller. */
struct hl_dbc_counters {
	uint64_t decoded; /* frames decoded */
	uint64_t unknown_id; /* frames whose ID is in no message */
	uint64_t short_frame; /* frames shorter than their message: rejected */
};

struct hl_dbc;

enum hl_dbc_parse_flags {
	/* Every irregularity of the file is an error, as before lenient loading. */
	HL_DBC_STRICT = 1 << 0,
};

/*
 * Parses a DBC text of len bytes (NUL bytes are an error). Returns 0, -EBADMSG (err: line,
 * column, what was expected), -ENOMEM.
 *
 * Lenient (flags 0, the default): what real files get wrong and can still be loaded is loaded,
 * each such place recorded as a warning (hl_dbc_warning: line, column, what was expected and
 * what was done instead); docs/dbc-compat.md lists them. A warning never changes what the
 * valid parts of the file decode to. Unknown sections are skipped with a warning in both modes.
 * HL_DBC_STRICT: those irregularities are errors with the messages their warnings start with.
 */
int hl_dbc_parse_flags(const char *text, size_t len, unsigned flags, struct hl_dbc **ret,
		       struct hl_dbc_error *ret_err);
/* As hl_dbc_parse_flags for a file; -errno when it cannot be read (err.msg says why, line 0). */
int hl_dbc_parse_file_flags(const char *path, unsigned flags, struct hl_dbc **ret,
			    struct hl_dbc_error *ret_err);
/* hl_dbc_parse_flags and hl_dbc_parse_file_flags with flags 0 (lenient). */
int hl_dbc_parse(const char *text, size_t len, struct hl_dbc **ret, struct hl_dbc_error *ret_err);
int hl_dbc_parse_file(const char *path, struct hl_dbc **ret, struct hl_dbc_error *ret_err);
void hl_dbc_free(struct hl_dbc *db);

const char *hl_dbc_version(const struct hl_dbc *db); /* VERSION string, "" if none */
const char *hl_dbc_comment(const struct hl_dbc *db); /* network CM_, or NULL */
int hl_dbc_n_warnings(const struct hl_dbc *db);
/* Warning i (skipped sections, and irregularities a lenient load read anyway): its place and
 * text, owned by the database. The library never prints them; the caller does, with the file. */
const char *hl_dbc_warning(const struct hl_dbc *db, int i, int *ret_line, int *ret_column);

int hl_dbc_n_nodes(const struct hl_dbc *db);
const char *hl_dbc_node(const struct hl_dbc *db, int i);
const char *hl_dbc_node_comment(const struct hl_dbc *db, int i);

int hl_dbc_n_messages(const struct hl_dbc *db);
const struct hl_dbc_message *hl_dbc_message(const struct hl_dbc *db, int i);
/* O(1): the message with can_id (id | HL_DBC_EFF_FLAG for extended IDs), or NULL. */
const struct hl_dbc_message *hl_dbc_find_id(const struct hl_dbc *db, uint32_t can_id);
const struct hl_dbc_message *hl_dbc_find_message(const struct hl_dbc *db, const char *name);
const struct hl_dbc_signal *hl_dbc_find_signal(const struct hl_dbc_message *m, const char *name);
/* The largest n_signals of any message: enough room for any decode. */
int hl_dbc_max_signals(const struct hl_dbc *db);

int hl_dbc_n_value_tables(const struct hl_dbc *db);
/* VAL_TABLE_ i: its name, and its n entries in *ret. */
const char *hl_dbc_value_table(const struct hl_dbc *db, int i, int *ret_n,
			       const struct hl_dbc_value_desc **ret);

int hl_dbc_n_attr_defs(const struct hl_dbc *db);
const struct hl_dbc_attr_def *hl_dbc_attr_def(const struct hl_dbc *db, int i);
/*
 * Value of attribute name on an object: 0 when set by BA_, 1 when it is the BA_DEF_DEF_
 * default, -ENOENT when the attribute is not defined for that kind of object or has no value.
 * node is a node name; m and s point into this database.
 */
int hl_dbc_network_attr(const struct hl_dbc *db, const char *name, struct hl_dbc_attr_value *ret);
int hl_dbc_node_attr(const struct hl_dbc *db, const char *node, const char *name,
		     struct hl_dbc_attr_value *ret);
int hl_dbc_message_attr(const struct hl_dbc *db, const struct hl_dbc_message *m, const char *name,
			struct hl_dbc_attr_value *ret);
int hl_dbc_signal_attr(const struct hl_dbc *db, const struct hl_dbc_message *m,
		       const struct hl_dbc_signal *s, const char *name,
		       struct hl_dbc_attr_value *ret);

/* --- codec (dbc/codec.c) --- */

/*
 * Decodes the signals of m present in the frame (all unmultiplexed ones, and the multiplexed
 * ones whose multiplexor selects them; never an unusable one) into ret_values (room for
 * m->n_signals), multiplexors before their dependents. Returns how many, -EMSGSIZE when len < m->size (nothing read), or
 * -ENOENT for the independent-signals pseudo message.
 * Allocates nothing.
 */
int hl_dbc_decode(const struct hl_dbc_message *m, const uint8_t *data, size_t len,
		  struct hl_dbc_value *ret_values);
/*
 * (dbc/database.c) Looks up can_id and decodes; counts the outcome in counters (may be NULL). Returns the number
 * of values, -ENOENT for an unknown ID, -EMSGSIZE for a short frame. *ret_msg is set on
 * success and for short frames.
 */
int hl_dbc_decode_frame(const struct hl_dbc *db, uint32_t can_id, const uint8_t *data, size_t len,
			struct hl_dbc_counters *counters, const struct hl_dbc_message **ret_msg,
			struct hl_dbc_value *ret_values);

/* Raw bits of one signal from a payload of len bytes: 0, or -EMSGSIZE if they lie beyond len. */
int hl_dbc_signal_get_raw(const struct hl_dbc_signal *s, const uint8_t *data, size_t len,
			  uint64_t *ret_raw);
/* Physical value of raw bits (sign, float/double, factor and offset). */
double hl_dbc_signal_phys(const struct hl_dbc_signal *s, uint64_t raw);
/*
 * Raw bits for a physical value: rounds to the nearest step of the factor. -ERANGE when the
 * value is not finite, outside [min, max] by more than half a step (when min < max), or does
 * not fit the signal's bits.
 */
int hl_dbc_signal_raw_from_phys(const struct hl_dbc_signal *s, double phys, uint64_t *ret_raw);
/* Writes raw bits (the low length bits of raw) into a payload of len bytes, other bits kept.
 * 0, or -EMSGSIZE if the signal lies beyond len. */
int hl_dbc_signal_set_raw(const struct hl_dbc_signal *s, uint64_t raw, uint8_t *data, size_t len);
/* hl_dbc_signal_raw_from_phys, then hl_dbc_signal_set_raw. */
int hl_dbc_signal_encode(const struct hl_dbc_signal *s, double phys, uint8_t *data, size_t len);
/* Whether s is present in a payload (its multiplexor chain selects it, and neither it nor a
 * multiplexor of the chain is unusable); len >= m->size. */
bool hl_dbc_signal_present(const struct hl_dbc_message *m, const struct hl_dbc_signal *s,
			   const uint8_t *data, size_t len);

#endif
