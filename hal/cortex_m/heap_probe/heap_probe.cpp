// Must NOT link for any board of the project: malloc and operator new need _sbrk, which the platform deliberately
// lacks (test <board>_link_rejects_the_heap, hal/cortex_m/CMakeLists.txt). If this ever links, the image would have a heap.
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
