/* Output of the C test on the host: through the C library's stdio. */
#include <stdio.h>

void vs_test_write(const char *s);

void vs_test_write(const char *s) { fputs(s, stdout); }
