/*
   What a text input file may not start with: a byte-order mark. flexslosh's text files (walls, probes, a
   prescribed motion's time series, ASCII STL, options files) are plain ASCII or UTF-8 without one; an editor
   that saves with a mark puts invisible bytes before the first word, so the readers name them (options files
   are read by PETSc, which took the mark for part of the first option: app/flexslosh.c looks first).
*/
#include "sys/fssys.h"

/*
   FSTextByteOrderMark - the byte-order mark text starts with, in words that show its bytes ("the bytes EF BB BF, a
   UTF-8 byte-order mark"), or NULL when it starts with none.

   Not collective

   Input Parameters:
+  text - the file's bytes
-  size - their number
*/
const char *FSTextByteOrderMark(const char text[], size_t size)
{
  const unsigned char *b = (const unsigned char *)text;

  if (size >= 3 && b[0] == 0xEF && b[1] == 0xBB && b[2] == 0xBF) return "the bytes EF BB BF, a UTF-8 byte-order mark";
  if (size >= 2 && b[0] == 0xFF && b[1] == 0xFE) return "the bytes FF FE, a UTF-16 byte-order mark (little-endian)";
  if (size >= 2 && b[0] == 0xFE && b[1] == 0xFF) return "the bytes FE FF, a UTF-16 byte-order mark (big-endian)";
  return NULL;
}
