# tlsmon_crypto: OpenSSL's libcrypto (SHA-256, PBKDF2, random bytes), Debian's shared library
# for every program, except a program with the property TLSMON_STATIC_CRYPTO, which links
# Debian's libcrypto.a instead. The reading program `tlsmon` does (cli/CMakeLists.txt):
# loading the shared library (21,000 relocations) costs about 4 ms of the 15 ms that
# `tlsmon status` may take, the few functions it calls cost nothing when linked in. That
# program must then load no other library that brings the shared libcrypto (the HTTP
# server's does; --as-needed leaves it out because no reading command calls it).
find_package(OpenSSL REQUIRED)
get_filename_component(_crypto_dir ${OPENSSL_CRYPTO_LIBRARY} DIRECTORY)
find_library(TLSMON_CRYPTO_STATIC NAMES libcrypto.a HINTS ${_crypto_dir} REQUIRED)

add_library(tlsmon_crypto INTERFACE)
set(_static "$<BOOL:$<TARGET_PROPERTY:TLSMON_STATIC_CRYPTO>>")
target_link_libraries(tlsmon_crypto INTERFACE "$<${_static}:${TLSMON_CRYPTO_STATIC}>"
                                              "$<$<NOT:${_static}>:OpenSSL::Crypto>")
target_include_directories(tlsmon_crypto SYSTEM INTERFACE ${OPENSSL_INCLUDE_DIR})
