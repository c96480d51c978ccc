// The heap bytes a piece of code leaves written: what a structure really
// holds in memory, to check the bytes it says it holds (memory_bytes()).
//
// Linking written_heap.cpp into a test program replaces the global operator
// new and delete. Between start() and stop(), every block handed out is
// filled with a byte pattern and remembered until it is freed; stop() counts,
// for each block still held, its bytes up to the last one that is not the
// pattern. A vector's reserve beyond its size is never written, so it counts
// as size() * sizeof(T): the bytes backed by memory, since the kernel backs
// a page only when it is first written. (A block whose last bytes were
// written with the pattern's own value counts a few bytes short.)
#pragma once

#include <cstddef>
#include <string>

namespace written_heap {

/// Starts remembering the blocks allocated from now on (any thread).
void start();

/// What the blocks allocated since start() and not freed hold.
struct Held {
  size_t bytes = 0;   ///< Their written bytes.
  size_t blocks = 0;  ///< How many.
  std::string sizes;  ///< Each one's written bytes, for a failure message.
};

/// Stops remembering and returns what the remembered blocks hold.
Held stop();

}  // namespace written_heap
