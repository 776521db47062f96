% expect: tcp_socket/1 is not allowed in a mission
mission.
:- tcp_socket(S), tcp_close_socket(S).
