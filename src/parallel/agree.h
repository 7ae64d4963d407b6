// Steps that every process takes on its own (each writes or reads its piece of a file) and
// that must then succeed or fail together: no process may go on to a collective, or leave a
// summary file pointing at a piece, that another process failed to write.
#pragma once

#include <functional>
#include <string>

#include "parallel/decomposition.h"

namespace cmcsurf {

// Runs f and returns "" or the message of the exception it threw.
std::string error_of(const std::function<void()>& f);

// Collective over d (null: this process alone): if any process's error is non-empty, every
// process throws std::runtime_error with the lowest failing rank's message, prefixed by
// "process R of P: " when there are several processes.
void agree_or_throw(const Decomposition* d, const std::string& error);

}  // namespace cmcsurf
