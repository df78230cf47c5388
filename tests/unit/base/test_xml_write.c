/* SPDX-License-Identifier: MIT */
/* XML text as the JUnit files and modelDescription.xml carry it: entities, no C0 controls. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "base/xml_write.h"

static char *written(const char *s)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	assert_non_null(f);
	hl_xml_write_text(f, s);
	assert_int_equal(fclose(f), 0);
	return buf;
}

static void xml_text_escapes(void **state)
{
	static const struct {
		const char *in, *out;
	} cases[] = {
		{ "plain left.row1_led01", "plain left.row1_led01" },
		{ "a<b & c>\"d\"", "a&lt;b &amp; c&gt;&quot;d&quot;" },
		{ "CAMB_HLeft[3]", "CAMB_HLeft[3]" },
		{ "tab\tnl\ncr\r", "tab\tnl\ncr\r" },
		{ "bell\a esc\x1b nul-free", "bell esc nul-free" },
		{ "caf\xc3\xa9", "caf\xc3\xa9" }, /* UTF-8 passes as is */
		{ "", "" },
	};

	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		char *s = written(cases[i].in);

		assert_string_equal(s, cases[i].out);
		free(s);
	}
	{
		char *s = written(NULL);

		assert_string_equal(s, "");
		free(s);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(xml_text_escapes),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
