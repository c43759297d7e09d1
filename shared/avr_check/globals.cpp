#include "check_common.h"

volatile float g_in = 0.5f;
volatile long g_out;
