// The umbrella header includes everything at once: no clashes between headers.
#include <articula/articula.h>
#include "check_common.h"
void check_articula() { g_out = articula::kMaxLineLength; }
