#pragma once
// Plugins are compiled with hidden visibility; the types they share with core (exceptions,
// interfaces) are marked NOETHER_API so their type information is one across libraries.
#define NOETHER_API __attribute__((visibility("default")))
