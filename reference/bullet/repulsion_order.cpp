#include "reference/bullet/repulsion_order.hpp"

#include <BulletSoftBody/btSoftBody.h>
#include <dlfcn.h>

namespace clothbench::reference {

namespace {

/// Bullet's initial generator state (btSoftBody.h:39).
constexpr unsigned long kInitialSeed = 243703;

/// The address of this file's copy of btSoftBody::applyRepulsionForce; taking it makes this
/// file emit the copy that uses this file's `seed`.
void* own_copy() {
  auto member = &btSoftBody::applyRepulsionForce;
  void* address = nullptr;
  static_assert(sizeof member >= sizeof address);
  __builtin_memcpy(&address, &member, sizeof address);
  return address;
}

}  // namespace

bool reset_repulsion_order() {
  seed = kInitialSeed;
  // the copy the dynamic linker binds Bullet's calls to is the first definition in the
  // process's lookup order: this executable's when it exports it
  static const bool reached =
      ::dlsym(RTLD_DEFAULT, "_ZN10btSoftBody19applyRepulsionForceEdb") == own_copy();
  return reached;
}

}  // namespace clothbench::reference
