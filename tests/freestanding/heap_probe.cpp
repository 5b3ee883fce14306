// The check's negative control: an object that needs the heap, exceptions and RTTI, which check_symbols.cmake must
// refuse (a check that passes everything would also pass the estimator). Compiled, inspected with nm, never linked.
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <typeinfo>

struct Base {
  virtual ~Base() = default;
};
struct Derived : Base {};

// Defined nowhere (the object is never linked): the allocations escape into it, so that no compiler may elide them
// (clang -O2 removes a malloc/free or new/delete pair whose memory nothing else sees).
extern "C" void heap_probe_sink(void* p);

extern "C" int heap_probe(int n, Base* b) {
  void* p = std::malloc(static_cast<std::size_t>(n));
  int* q = new int(n);
  const bool derived = dynamic_cast<Derived*>(b) != nullptr;
  if (n < 0) throw std::runtime_error("negative");
  heap_probe_sink(p);
  heap_probe_sink(q);
  const int r = *q + (p != nullptr ? 1 : 0) + (derived ? 1 : 0);
  std::free(p);
  delete q;
  return r;
}
