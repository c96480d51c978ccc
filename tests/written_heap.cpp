#include "written_heap.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>

namespace written_heap {
namespace {

constexpr unsigned char kPattern = 0xA5;
// Every block starts kFront bytes (or its alignment, if larger) into what
// aligned_alloc gives, with its header just before it.
constexpr size_t kFront = 64;

struct Header {
  size_t size;
  std::atomic<bool> remembered;
  Header* prev;
  Header* next;
};
static_assert(sizeof(Header) <= kFront);

std::mutex mu;
std::atomic<bool> recording{false};
Header* first = nullptr;  // the remembered blocks, under mu

size_t front(size_t align) {
  return std::max(kFront, align);
}
Header* header_of(void* p) {
  return reinterpret_cast<Header*>(static_cast<char*>(p) - sizeof(Header));
}

void* allocate(size_t size, size_t align) {
  const size_t f = front(align);
  const size_t total = (f + std::max<size_t>(size, 1) + f - 1) / f * f;
  char* base = static_cast<char*>(std::aligned_alloc(f, total));
  if (base == nullptr) return nullptr;
  void* p = base + f;
  Header* h = new (header_of(p)) Header{size, {false}, nullptr, nullptr};
  if (recording.load(std::memory_order_relaxed)) {
    std::memset(p, kPattern, size);
    std::lock_guard<std::mutex> lock(mu);
    h->remembered = true;
    h->next = first;
    if (first != nullptr) first->prev = h;
    first = h;
  }
  return p;
}

void release(void* p, size_t align) {
  if (p == nullptr) return;
  Header* h = header_of(p);
  if (h->remembered.load()) {
    std::lock_guard<std::mutex> lock(mu);
    if (h->remembered) {
      if (h->prev != nullptr) h->prev->next = h->next;
      if (h->next != nullptr) h->next->prev = h->prev;
      if (first == h) first = h->next;
    }
  }
  h->~Header();
  std::free(static_cast<char*>(p) - front(align));
}

void* allocate_or_throw(size_t size, size_t align) {
  void* p = allocate(size, align);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

void start() {
  std::lock_guard<std::mutex> lock(mu);
  recording = true;
}

Held stop() {
  std::lock_guard<std::mutex> lock(mu);
  recording = false;
  Held held;
  for (Header* h = first; h != nullptr;) {
    const unsigned char* bytes = reinterpret_cast<const unsigned char*>(h + 1);
    size_t written = h->size;
    while (written > 0 && bytes[written - 1] == kPattern) --written;
    held.bytes += written;
    held.blocks++;
    held.sizes += ' ';
    held.sizes += std::to_string(written);
    Header* next = h->next;
    h->remembered = false;
    h->prev = h->next = nullptr;
    h = next;
  }
  first = nullptr;
  return held;
}

}  // namespace written_heap

using written_heap::allocate;
using written_heap::allocate_or_throw;
using written_heap::release;

constexpr size_t kPlain = __STDCPP_DEFAULT_NEW_ALIGNMENT__;

void* operator new(size_t n) {
  return allocate_or_throw(n, kPlain);
}
void* operator new[](size_t n) {
  return allocate_or_throw(n, kPlain);
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  return allocate(n, kPlain);
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  return allocate(n, kPlain);
}
void* operator new(size_t n, std::align_val_t a) {
  return allocate_or_throw(n, size_t(a));
}
void* operator new[](size_t n, std::align_val_t a) {
  return allocate_or_throw(n, size_t(a));
}
void* operator new(size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(n, size_t(a));
}
void* operator new[](size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(n, size_t(a));
}
void operator delete(void* p) noexcept {
  release(p, kPlain);
}
void operator delete[](void* p) noexcept {
  release(p, kPlain);
}
void operator delete(void* p, size_t) noexcept {
  release(p, kPlain);
}
void operator delete[](void* p, size_t) noexcept {
  release(p, kPlain);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  release(p, kPlain);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  release(p, kPlain);
}
void operator delete(void* p, std::align_val_t a) noexcept {
  release(p, size_t(a));
}
void operator delete[](void* p, std::align_val_t a) noexcept {
  release(p, size_t(a));
}
void operator delete(void* p, size_t, std::align_val_t a) noexcept {
  release(p, size_t(a));
}
void operator delete[](void* p, size_t, std::align_val_t a) noexcept {
  release(p, size_t(a));
}
void operator delete(void* p, std::align_val_t a, const std::nothrow_t&) noexcept {
  release(p, size_t(a));
}
void operator delete[](void* p, std::align_val_t a, const std::nothrow_t&) noexcept {
  release(p, size_t(a));
}
