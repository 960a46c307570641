// placeholder
#include "bindings.h"
