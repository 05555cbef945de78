// SPDX-License-Identifier: MIT
/// @file relief_tracer_instances.cpp
/// The tracers the project's programs and tests use, compiled once here (see the end of
/// relief_tracer.h): ReliefTracer<float> and ReliefTracer<double> with the default search, and
/// their search for 8- and 16-bit distance codes.
#include "cellrelief/trace/relief_tracer.h"

#ifndef CELLRELIEF_EXTERN_RELIEF_TRACER
#error "compiled with CELLRELIEF_EXTERN_RELIEF_TRACER, as the target cellrelief_trace_instances defines it"
#endif

namespace cellrelief::trace {
CELLRELIEF_RELIEF_TRACER_INSTANCES(, float)
CELLRELIEF_RELIEF_TRACER_INSTANCES(, double)
}  // namespace cellrelief::trace
