// Body descriptions in JSON (src/io/body_json.cpp).
#include "ringlet/body_json.h"
