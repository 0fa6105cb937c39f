"""The classic snake game of thesis ch. 5.6: pure game logic, a text display, keyboard and swipe control."""
