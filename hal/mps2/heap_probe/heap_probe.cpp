// Must NOT link for the mps2 boards: malloc and operator new need _sbrk, which the platform deliberately lacks
// (test mps2_link_rejects_the_heap). If this ever links, the image would have a heap.
#include <cstdlib>
#include <new>

int main() {
  void* volatile p = std::malloc(16);
  int* volatile q = new int(1);
  const int r = (p != nullptr ? 1 : 0) + *q;
  std::free(p);
  delete q;
  return r;
}
